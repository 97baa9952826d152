#pragma once
// nav_msgs/Odometry <-> odometry pose + 6x6 covariance, and the covariance array helpers used
// by every message with a float64[36] (Odometry, Link information, OdomInfo).
//
// The odometry-lost convention of rtabmap_ros: when odometry cannot compute a pose it publishes
// a *null* pose (all zeros, including the quaternion) with 9999 on the covariance diagonal, so
// consumers that only look at the covariance also see it is worthless. odometryToMsg writes that
// for a null Transform; odometryFromMsg reads an all-zero quaternion, or an x variance of 9999
// or more, back as a null pose with that covariance. (Only x: planar wheel odometry puts huge
// variances on z, roll and pitch, which it does not observe.)
#include <Eigen/Core>
#include <boost/array.hpp>
#include <nav_msgs/Odometry.h>
#include <std_msgs/Header.h>

#include <optional>
#include <string>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_conversions {

using Covariance6 = Eigen::Matrix<double, 6, 6>;

// The covariance of a lost pose (diagonal value).
inline constexpr double kLostCovariance = 9999.0;

// Row-major float64[36] (x y z roll pitch yaw), as geometry_msgs and rtabmap_ros/Link store it.
boost::array<double, 36> covarianceToMsg(const Covariance6& covariance);
Covariance6 covarianceFromMsg(const boost::array<double, 36>& values);

// header: stamp and odometry frame (frame_id, e.g. "odom"); childFrameId: the base frame.
// The twist is left zero (the core's odometry pose carries no velocity).
nav_msgs::Odometry odometryToMsg(const rtabmap::Transform& pose, const Covariance6& covariance,
                                 const std_msgs::Header& header, const std::string& childFrameId);

struct OdometryReading {
  double stamp = 0.0;
  std::string frameId;       // odometry frame
  std::string childFrameId;  // base frame
  rtabmap::Transform pose;   // null when lost
  Covariance6 covariance = Covariance6::Identity();
  Eigen::Matrix<double, 6, 1> twist = Eigen::Matrix<double, 6, 1>::Zero();  // vx vy vz wx wy wz
  Covariance6 twistCovariance = Covariance6::Zero();
  bool lost() const { return pose.isNull(); }
};

// Errors: NaN or infinite pose, twist or covariance; an empty frame_id.
std::optional<OdometryReading> odometryFromMsg(const nav_msgs::Odometry& msg, std::string* error = nullptr);

}  // namespace rtabmap_conversions

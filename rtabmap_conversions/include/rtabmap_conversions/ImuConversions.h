#pragma once
// sensor_msgs/Imu <-> rtabmap::IMU.
//
// An IMU without orientation (most raw IMUs) says so as sensor_msgs/Imu documents it:
// orientation_covariance[0] = -1 (and the quaternion is then meaningless). The core says it
// with an all-zero quaternion. Both directions map one to the other. Covariances are row-major
// 3x3 arrays on the ROS side.
#include <sensor_msgs/Imu.h>
#include <std_msgs/Header.h>

#include <optional>
#include <string>

#include "rtabmap_core/geometry/IMU.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_conversions {

sensor_msgs::Imu imuToMsg(const rtabmap::IMU& imu, const std_msgs::Header& header);
// localTransform: base frame -> IMU frame (header.frame_id). A non-unit quaternion is
// normalised; an all-zero one (drivers that forget the -1 marker) means no orientation too.
// Errors: NaN or infinite values (except in an orientation declared absent).
std::optional<rtabmap::IMU> imuFromMsg(const sensor_msgs::Imu& msg,
                                       const rtabmap::Transform& localTransform = rtabmap::Transform::Identity(),
                                       std::string* error = nullptr);

}  // namespace rtabmap_conversions

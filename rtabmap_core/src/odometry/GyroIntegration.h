#pragma once
// The rotation a raw IMU's gyroscope measured between two frames: angular velocities in the
// robot's base frame, integrated over time. Odometry takes it as the rotation of its motion guess
// when the frames carry no orientation (the gyroscope needs no filter and no gravity: a bias of
// 0.01 rad/s turns a 0.1 s guess by 0.001 rad). Private to the odometry area.
#include <Eigen/Core>

#include <deque>
#include <optional>

#include "rtabmap_core/geometry/IMU.h"

namespace rtabmap::odometry_detail {

class GyroIntegration {
 public:
  // maxGap: samples farther apart than this (s) do not cover the time between them (the IMU
  // stopped or its messages were lost), nor does a sample cover more than this beyond itself.
  // keep: history kept behind the newest sample (s), however long odometry stays lost.
  explicit GyroIntegration(double maxGap = 0.05, double keep = 10.0) : maxGap_(maxGap), keep_(keep) {}

  // A raw sample: its angular velocity (rad/s, in the IMU's frame) brought to the base through
  // IMU::localTransform. False (nothing kept) for a sample without an angular velocity, not
  // finite, or not after the previous one.
  bool add(double stamp, const IMU& imu);
  // The rotation of the base from t0 to t1 (expressed at t0), integrated over the samples (the
  // mean of two consecutive ones over the time between them; at each end of [t0, t1], the
  // nearest sample inside held up to maxGap). None when the samples do not cover [t0, t1].
  std::optional<Eigen::Matrix3d> rotationBetween(double t0, double t1) const;
  // Forgets the samples no integration from t on needs.
  void dropBefore(double t);
  void clear() { samples_.clear(); }
  bool empty() const { return samples_.empty(); }
  size_t size() const { return samples_.size(); }

 private:
  struct Sample {
    double stamp;
    Eigen::Vector3d angularVelocity;  // base frame
  };
  double maxGap_, keep_;
  std::deque<Sample> samples_;  // by increasing stamp
};

}  // namespace rtabmap::odometry_detail

#pragma once
// Wheel odometry of the simulated differential-drive robot: the true motion, integrated with
// the errors real wheel encoders make.
//
// Each true increment (from the robot's previous pose to its current one, in the previous
// pose's frame) is read as a travelled distance ds and a heading change dyaw, perturbed:
//   ds'   = ds (1 + scaleBias) + N(0, translation^2 |ds|)
//   dyaw' = dyaw + yawBiasPerMetre |ds| + N(0, rotation^2 |dyaw| + rotationPerMetre^2 |ds|)
// (variances grow with the motion, so the error does not depend on how often it is sampled;
// the biases are systematic: a wheel radius and a wheel separation a little off), then applied
// with the true direction of travel, rotated by half the heading error. With all terms zero the
// odometry is exactly the true motion: odom_k = gt_0^-1 * gt_k.
//
// The covariance of the motion since a mark (for each consumer: the previous frame, the
// previous odometry message) is propagated with the same model (first order, planar x, y, yaw).
#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "rtabmap_core/sim/Pose2.h"
#include "rtabmap_core/sim/Random.h"

namespace rtabmap::sim {

struct OdometryNoise {
  double translation = 0.02;       // m per sqrt(m): 2 cm standard deviation after 1 m
  double rotation = 0.03;          // rad per sqrt(rad) turned
  double rotationPerMetre = 0.01;  // rad per sqrt(m) driven
  double scaleBias = 0.005;        // systematic distance error: +0.5 %
  double yawBiasPerMetre = 0.002;  // systematic heading drift: 0.11 deg per metre driven
  static OdometryNoise none() { return {0, 0, 0, 0, 0}; }
};

// Relative motion since a mark and its covariance (x, y, yaw in the mark's frame).
struct OdometryIncrement {
  Pose2 motion;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

class WheelOdometry {
 public:
  // `consumers` independent increments are tracked (e.g. 0 = frames, 1 = odometry messages).
  WheelOdometry(const OdometryNoise& noise, uint64_t seed, int consumers = 2);

  // Starts over at the identity (odometry reset) from the robot's current true pose.
  void reset(const Pose2& truePose);
  // Integrates the true motion to `truePose`.
  void update(const Pose2& truePose);
  // The odometry pose (in the odometry frame: identity where reset was called).
  const Pose2& pose() const { return pose_; }
  // Motion and covariance since consumer c's last take, and starts a new one.
  OdometryIncrement take(int consumer);
  const OdometryNoise& noise() const { return noise_; }

 private:
  OdometryNoise noise_;
  Rng rng_;
  Pose2 lastTrue_;
  Pose2 pose_;
  std::vector<OdometryIncrement> increments_;
};

}  // namespace rtabmap::sim

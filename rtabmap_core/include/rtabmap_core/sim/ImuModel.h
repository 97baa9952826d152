#pragma once
// The simulated IMU (a consumer MEMS unit, e.g. BMI088-class) on the planar robot, axes aligned
// with the base. Each sample reports the *mean* angular velocity and specific force over its
// period (as an IMU's anti-aliasing filter does), so summing gyro * period gives exactly the
// yaw change, and at rest the accelerometer reads +g up (specific force, REP-145).
//
// The robot only turns about z, and the IMU sits on the z axis, so there is no lever-arm term:
//   gyro  = (0, 0, omega)
//   accel = (dv/dt, v * omega, g)   (forward, centripetal to the left, gravity reaction)
// plus white noise (density * sqrt(rate)) and a bias that starts at a random offset and
// random-walks (all deterministic for a seed). Orientation is not estimated (unknown, as in
// EuRoC's raw IMU).
#include <Eigen/Core>

#include <cstdint>

#include "rtabmap_core/sim/Random.h"

namespace rtabmap::sim {

constexpr double kGravity = 9.80665;

struct ImuNoise {
  double gyroNoiseDensity = 1.7e-4;    // rad/s/sqrt(Hz)
  double accelNoiseDensity = 2.0e-3;   // m/s^2/sqrt(Hz)
  double gyroBiasWalk = 2.0e-5;        // rad/s^2/sqrt(Hz)
  double accelBiasWalk = 3.0e-3;       // m/s^3/sqrt(Hz)
  double gyroBiasInitial = 2.0e-3;     // rad/s, standard deviation of the turn-on bias
  double accelBiasInitial = 0.03;      // m/s^2
  static ImuNoise none() { return {0, 0, 0, 0, 0, 0}; }
};

struct ImuSample {
  double stamp = 0.0;
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d linearAcceleration = Eigen::Vector3d::Zero();
};

class ImuModel {
 public:
  ImuModel(const ImuNoise& noise, double rate, uint64_t seed);
  // Accumulates one simulation step of true motion.
  void accumulate(double dt, double v, double omega, double acceleration);
  // The sample over the steps accumulated since the last one (mean, plus noise and bias).
  ImuSample sample(double stamp);
  const ImuNoise& noise() const { return noise_; }
  double rate() const { return rate_; }
  // Variances to report in sensor_msgs/Imu covariances (per axis, per sample).
  double gyroVariance() const;
  double accelVariance() const;

 private:
  ImuNoise noise_;
  double rate_;
  Rng rng_;
  Eigen::Vector3d gyroBias_;
  Eigen::Vector3d accelBias_;
  Eigen::Vector3d sumGyro_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d sumAccel_ = Eigen::Vector3d::Zero();
  double sumTime_ = 0.0;
};

}  // namespace rtabmap::sim

#include "rtabmap_core/sim/ImuModel.h"

#include <cmath>
#include <stdexcept>

namespace rtabmap::sim {

namespace {
Eigen::Vector3d normal3(Rng& rng, double sigma) {
  if (sigma <= 0.0) return Eigen::Vector3d::Zero();
  const double x = rng.normal();
  const double y = rng.normal();
  const double z = rng.normal();
  return sigma * Eigen::Vector3d(x, y, z);
}
}  // namespace

ImuModel::ImuModel(const ImuNoise& noise, double rate, uint64_t seed) : noise_(noise), rate_(rate), rng_(seed, "imu") {
  if (!(rate > 0.0)) throw std::invalid_argument("ImuModel: rate must be > 0");
  gyroBias_ = normal3(rng_, noise.gyroBiasInitial);
  accelBias_ = normal3(rng_, noise.accelBiasInitial);
}

void ImuModel::accumulate(double dt, double v, double omega, double acceleration) {
  sumGyro_ += dt * Eigen::Vector3d(0.0, 0.0, omega);
  sumAccel_ += dt * Eigen::Vector3d(acceleration, v * omega, kGravity);
  sumTime_ += dt;
}

ImuSample ImuModel::sample(double stamp) {
  ImuSample s;
  s.stamp = stamp;
  const double period = sumTime_ > 0.0 ? sumTime_ : 1.0 / rate_;
  const Eigen::Vector3d gyro = sumTime_ > 0.0 ? Eigen::Vector3d(sumGyro_ / sumTime_) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d accel = sumTime_ > 0.0 ? Eigen::Vector3d(sumAccel_ / sumTime_) : Eigen::Vector3d(0, 0, kGravity);
  // White noise of a mean over `period`: density / sqrt(period).
  s.angularVelocity = gyro + gyroBias_ + normal3(rng_, noise_.gyroNoiseDensity / std::sqrt(period));
  s.linearAcceleration = accel + accelBias_ + normal3(rng_, noise_.accelNoiseDensity / std::sqrt(period));
  gyroBias_ += normal3(rng_, noise_.gyroBiasWalk * std::sqrt(period));
  accelBias_ += normal3(rng_, noise_.accelBiasWalk * std::sqrt(period));
  sumGyro_.setZero();
  sumAccel_.setZero();
  sumTime_ = 0.0;
  return s;
}

double ImuModel::gyroVariance() const { return noise_.gyroNoiseDensity * noise_.gyroNoiseDensity * rate_; }
double ImuModel::accelVariance() const { return noise_.accelNoiseDensity * noise_.accelNoiseDensity * rate_; }

}  // namespace rtabmap::sim

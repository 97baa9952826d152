#include "OdometryPrior.h"

#include <Eigen/Cholesky>

namespace rtabmap {

Transform fuseWithOdometryPrior(const Transform& registered, const Eigen::Matrix<double, 6, 6>& information,
                                const Transform& odometry, double prior) {
  if (!(prior > 0.0) || registered.isNull() || odometry.isNull() || !information.allFinite()) return registered;
  const Transform correction = odometry.inverse() * registered;
  double x, y, z, roll, pitch, yaw;
  correction.getTranslationAndEulerAngles(x, y, z, roll, pitch, yaw);
  Eigen::Matrix<double, 6, 1> d;
  d << x, y, z, roll, pitch, yaw;

  const double sigma = 0.01 + prior * odometry.getNorm();
  Eigen::Matrix<double, 6, 6> odometryInformation = Eigen::Matrix<double, 6, 6>::Zero();
  odometryInformation.topLeftCorner<3, 3>() = Eigen::Matrix3d::Identity() / (sigma * sigma);

  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> solver(information + odometryInformation);
  if (solver.info() != Eigen::Success || !solver.isPositive()) return registered;
  const Eigen::Matrix<double, 6, 1> fused = solver.solve(information * d);
  if (!fused.allFinite()) return registered;
  return odometry * Transform(fused(0), fused(1), fused(2), fused(3), fused(4), fused(5));
}

}  // namespace rtabmap

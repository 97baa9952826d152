#pragma once
// Residual of a gravity link (kGravity, from == to: the orientation of the node in the world
// frame as an IMU measures it; only roll and pitch are observable) on one SE3 pose
// (internal header).
//
// The up axis of the world, seen in the body frame, must match the measured one:
//   r = (R' u - Rm' u) / sigma,  u = (0, 0, 1)
// With R perturbed on the right (Se3Manifold.h): (R Exp(d))' u = Exp(-d) R' u ~ R' u + [R' u]x d,
// so d r / d d_r = [R' u]x / sigma and d r / d d_t = 0. Yaw does not change r: gravity leaves the
// heading free.
#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include "PoseMath.h"

namespace rtabmap::optimizer_internal {

class GravityCost final : public ceres::SizedCostFunction<3, 7> {
 public:
  GravityCost(const Eigen::Quaterniond& measured, double sigma)
      : measuredUp_(measured.conjugate() * Eigen::Vector3d::UnitZ()), invSigma_(1.0 / sigma) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Eigen::Map<const Eigen::Quaterniond> q(parameters[0] + 3);
    const Eigen::Vector3d up = q.conjugate() * Eigen::Vector3d::UnitZ();
    Eigen::Map<Eigen::Vector3d>{residuals} = invSigma_ * (up - measuredUp_);
    if (jacobians && jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, 3, 7, Eigen::RowMajor>> out(jacobians[0]);
      out.setZero();
      out.block<3, 3>(0, 3) = invSigma_ * skew(up);
    }
    return true;
  }

 private:
  Eigen::Vector3d measuredUp_;
  double invSigma_;
};

struct GravityFunctor {
  GravityFunctor(const Eigen::Quaterniond& measured, double sigma)
      : measuredUp(measured.conjugate() * Eigen::Vector3d::UnitZ()), invSigma(1.0 / sigma) {}
  template <typename T>
  bool operator()(const T* x, T* residuals) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(x + 3);
    const Eigen::Matrix<T, 3, 1> up = q.conjugate() * Eigen::Matrix<T, 3, 1>(T(0), T(0), T(1));
    for (int i = 0; i < 3; ++i) residuals[i] = T(invSigma) * (up[i] - T(measuredUp[i]));
    return true;
  }
  Eigen::Vector3d measuredUp;
  double invSigma;
};

inline ceres::CostFunction* makeGravityCost(const Eigen::Quaterniond& measured, double sigma,
                                            bool autoDiff) {
  if (autoDiff) {
    return new ceres::AutoDiffCostFunction<GravityFunctor, 3, 7>(new GravityFunctor(measured, sigma));
  }
  return new GravityCost(measured, sigma);
}

}  // namespace rtabmap::optimizer_internal

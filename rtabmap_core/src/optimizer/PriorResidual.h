#pragma once
// Residuals of an absolute pose prior (kPosePrior links: GPS, ground truth) on one pose
// (internal header). Same error as a relative link with Xi = identity: E = Z^-1 * X.
//
// SE2: e = [Rz' (t - tz), wrap(theta - theta_z)]; d e/d t = [Rz'; 0], d e/d theta = [0, 0, 1]'.
// SE3: e = [Rz' (t - tz), qvec(qz^-1 q)] (w >= 0); with the tangent increment of Se3Manifold.h,
//      d e_t/d t = Rz', d qvec/d r = G = 1/2 (w I + [v]x) of the error quaternion (w, v).
#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include <cmath>

#include "PoseMath.h"

namespace rtabmap::optimizer_internal {

class Se2PriorCost final : public ceres::SizedCostFunction<3, 3> {
 public:
  Se2PriorCost(const Eigen::Vector3d& z, const Eigen::Matrix3d& sqrtInfo)
      : z_(z), u_(sqrtInfo), cz_(std::cos(z[2])), sz_(std::sin(z[2])) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* x = parameters[0];
    const double dx = x[0] - z_[0], dy = x[1] - z_[1];
    const Eigen::Vector3d e(cz_ * dx + sz_ * dy, -sz_ * dx + cz_ * dy, wrapAngle(x[2] - z_[2]));
    Eigen::Map<Eigen::Vector3d>{residuals} = u_ * e;
    if (jacobians && jacobians[0]) {
      Eigen::Matrix3d j;
      j << cz_, sz_, 0.0,
           -sz_, cz_, 0.0,
           0.0, 0.0, 1.0;
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>{jacobians[0]} = u_ * j;
    }
    return true;
  }

 private:
  Eigen::Vector3d z_;
  Eigen::Matrix3d u_;
  double cz_, sz_;
};

class Se3PriorCost final : public ceres::SizedCostFunction<6, 7> {
 public:
  Se3PriorCost(const Eigen::Vector3d& tz, const Eigen::Quaterniond& qz,
               const Eigen::Matrix<double, 6, 6>& sqrtInfo)
      : tz_(tz), qzInv_(qz.conjugate().normalized()), u_(sqrtInfo) {
    rzT_ = qzInv_.toRotationMatrix();
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Eigen::Map<const Eigen::Vector3d> t(parameters[0]);
    const Eigen::Map<const Eigen::Quaterniond> q(parameters[0] + 3);
    Eigen::Quaterniond qE = qzInv_ * q;
    if (qE.w() < 0.0) qE.coeffs() = -qE.coeffs();
    Eigen::Matrix<double, 6, 1> e;
    e.head<3>() = rzT_ * (t - tz_);
    e.tail<3>() = qE.vec();
    Eigen::Map<Eigen::Matrix<double, 6, 1>>{residuals} = u_ * e;
    if (jacobians && jacobians[0]) {
      Eigen::Matrix<double, 6, 6> j = Eigen::Matrix<double, 6, 6>::Zero();
      j.block<3, 3>(0, 0) = rzT_;
      j.block<3, 3>(3, 3) = 0.5 * qE.w() * Eigen::Matrix3d::Identity() + 0.5 * skew(qE.vec());
      Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> out(jacobians[0]);
      out.leftCols<6>() = u_ * j;
      out.col(6).setZero();
    }
    return true;
  }

 private:
  Eigen::Vector3d tz_;
  Eigen::Quaterniond qzInv_;
  Eigen::Matrix3d rzT_;
  Eigen::Matrix<double, 6, 6> u_;
};

// Auto-diff versions.
struct Se2PriorFunctor {
  Se2PriorFunctor(const Eigen::Vector3d& z, const Eigen::Matrix3d& sqrtInfo) : z(z), u(sqrtInfo) {}
  template <typename T>
  bool operator()(const T* x, T* residuals) const {
    const double cz = std::cos(z[2]), sz = std::sin(z[2]);
    const T dx = x[0] - T(z[0]), dy = x[1] - T(z[1]);
    T e[3] = {T(cz) * dx + T(sz) * dy, T(-sz) * dx + T(cz) * dy, wrapAngle(x[2] - T(z[2]))};
    for (int r = 0; r < 3; ++r) {
      residuals[r] = T(0.0);
      for (int k = r; k < 3; ++k) residuals[r] += T(u(r, k)) * e[k];
    }
    return true;
  }
  Eigen::Vector3d z;
  Eigen::Matrix3d u;
};

struct Se3PriorFunctor {
  Se3PriorFunctor(const Eigen::Vector3d& tz, const Eigen::Quaterniond& qz,
                  const Eigen::Matrix<double, 6, 6>& sqrtInfo)
      : tz(tz), qzInv(qz.conjugate().normalized()), u(sqrtInfo) {}
  template <typename T>
  bool operator()(const T* x, T* residuals) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(x);
    const Eigen::Map<const Eigen::Quaternion<T>> q(x + 3);
    const Eigen::Quaternion<T> qzInvT = qzInv.template cast<T>();
    Eigen::Quaternion<T> qE = qzInvT * q;
    if (qE.w() < T(0.0)) qE.coeffs() = -qE.coeffs();
    Eigen::Matrix<T, 6, 1> e;
    e.template head<3>() = qzInvT * (t - tz.template cast<T>());
    e.template tail<3>() = qE.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>>{residuals} = u.template cast<T>() * e;
    return true;
  }
  Eigen::Vector3d tz;
  Eigen::Quaterniond qzInv;
  Eigen::Matrix<double, 6, 6> u;
};

inline ceres::CostFunction* makeSe2PriorCost(const Eigen::Vector3d& z,
                                             const Eigen::Matrix3d& sqrtInfo, bool autoDiff) {
  if (autoDiff) {
    return new ceres::AutoDiffCostFunction<Se2PriorFunctor, 3, 3>(new Se2PriorFunctor(z, sqrtInfo));
  }
  return new Se2PriorCost(z, sqrtInfo);
}

inline ceres::CostFunction* makeSe3PriorCost(const Eigen::Vector3d& tz, const Eigen::Quaterniond& qz,
                                             const Eigen::Matrix<double, 6, 6>& sqrtInfo,
                                             bool autoDiff) {
  if (autoDiff) {
    return new ceres::AutoDiffCostFunction<Se3PriorFunctor, 6, 7>(
        new Se3PriorFunctor(tz, qz, sqrtInfo));
  }
  return new Se3PriorCost(tz, qz, sqrtInfo);
}

}  // namespace rtabmap::optimizer_internal

#pragma once
// The residual of a relative SE3 link (internal header).
//
// r = U * e, e = [t, qvec] of E = Z^-1 * (Xi^-1 * Xj) with E's quaternion w >= 0, U' U = Omega in
// g2o's convention (Chi2.h), so |r|^2 is the link's g2o chi2. Poses are double[7] (PoseMath.h).
//
// Jacobians, with respect to the tangent increment d = (d_t, d_r) of Se3TangentManifold
// (t + d_t, R * Exp(d_r)); R_D = Ri' Rj, t_D = Ri' (tj - ti), E = (R_E, t_E):
//   t_E = Rz' (t_D - tz)
//     d/d t_j = Rz' Ri',  d/d t_i = -Rz' Ri',  d/d r_i = Rz' [t_D]x,  d/d r_j = 0
//   R_E perturbs on the right: by d_r_j for Xj, and by -R_D' d_r_i for Xi
//   (Exp(-d) R_D = R_D Exp(-R_D' d)); for a unit quaternion q = (w, v),
//   vec(q * (1, phi/2)) = v + 1/2 (w I + [v]x) phi, so with G = 1/2 (w I + [v]x):
//     d qvec / d r_j = G,  d qvec / d r_i = -G R_D'
// Each block Jacobian Ceres asks for is 6x7 (ambient); the 7th column is zero (Se3Manifold.h).
#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include "PoseMath.h"

namespace rtabmap::optimizer_internal {

using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Matrix67RowMajor = Eigen::Matrix<double, 6, 7, Eigen::RowMajor>;

class Se3EdgeCost final : public ceres::SizedCostFunction<6, 7, 7> {
 public:
  Se3EdgeCost(const Eigen::Vector3d& tz, const Eigen::Quaterniond& qz, const Matrix6& sqrtInfo)
      : tz_(tz), qzInv_(qz.conjugate().normalized()), u_(sqrtInfo) {
    rzT_ = qzInv_.toRotationMatrix();
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Eigen::Map<const Eigen::Vector3d> ti(parameters[0]), tj(parameters[1]);
    const Eigen::Map<const Eigen::Quaterniond> qi(parameters[0] + 3), qj(parameters[1] + 3);
    const Eigen::Matrix3d riT = qi.toRotationMatrix().transpose();
    const Eigen::Vector3d tD = riT * (tj - ti);
    const Eigen::Quaterniond qD = qi.conjugate() * qj;
    Eigen::Quaterniond qE = qzInv_ * qD;
    if (qE.w() < 0.0) qE.coeffs() = -qE.coeffs();
    Eigen::Matrix<double, 6, 1> e;
    e.head<3>() = rzT_ * (tD - tz_);
    e.tail<3>() = qE.vec();
    Eigen::Map<Eigen::Matrix<double, 6, 1>>{residuals} = u_ * e;
    if (!jacobians) return true;

    const Eigen::Matrix3d rzTriT = rzT_ * riT;
    Eigen::Matrix3d g = 0.5 * qE.w() * Eigen::Matrix3d::Identity() + 0.5 * skew(qE.vec());
    if (jacobians[0]) {
      Matrix6 j = Matrix6::Zero();
      j.block<3, 3>(0, 0) = -rzTriT;
      j.block<3, 3>(0, 3) = rzT_ * skew(tD);
      j.block<3, 3>(3, 3) = -g * qD.toRotationMatrix().transpose();
      Eigen::Map<Matrix67RowMajor> out(jacobians[0]);
      out.leftCols<6>() = u_ * j;
      out.col(6).setZero();
    }
    if (jacobians[1]) {
      Matrix6 j = Matrix6::Zero();
      j.block<3, 3>(0, 0) = rzTriT;
      j.block<3, 3>(3, 3) = g;
      Eigen::Map<Matrix67RowMajor> out(jacobians[1]);
      out.leftCols<6>() = u_ * j;
      out.col(6).setZero();
    }
    return true;
  }

 private:
  Eigen::Vector3d tz_;
  Eigen::Quaterniond qzInv_;
  Eigen::Matrix3d rzT_;
  Matrix6 u_;
};

// The same residual for automatic differentiation (with Ceres's quaternion manifold).
struct Se3EdgeFunctor {
  Se3EdgeFunctor(const Eigen::Vector3d& tz, const Eigen::Quaterniond& qz, const Matrix6& sqrtInfo)
      : tz(tz), qzInv(qz.conjugate().normalized()), u(sqrtInfo) {}

  template <typename T>
  bool operator()(const T* xi, const T* xj, T* residuals) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> ti(xi), tj(xj);
    const Eigen::Map<const Eigen::Quaternion<T>> qi(xi + 3), qj(xj + 3);
    const Eigen::Quaternion<T> qiInv = qi.conjugate();
    const Eigen::Matrix<T, 3, 1> tD = qiInv * (tj - ti);
    const Eigen::Quaternion<T> qzInvT = qzInv.template cast<T>();
    Eigen::Quaternion<T> qE = qzInvT * (qiInv * qj);
    if (qE.w() < T(0.0)) qE.coeffs() = -qE.coeffs();
    Eigen::Matrix<T, 6, 1> e;
    e.template head<3>() = qzInvT * (tD - tz.template cast<T>());
    e.template tail<3>() = qE.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>>{residuals} = u.template cast<T>() * e;
    return true;
  }

  Eigen::Vector3d tz;
  Eigen::Quaterniond qzInv;
  Matrix6 u;
};

inline ceres::CostFunction* makeSe3EdgeCost(const Eigen::Vector3d& tz, const Eigen::Quaterniond& qz,
                                            const Matrix6& sqrtInfo, bool autoDiff) {
  if (autoDiff) {
    return new ceres::AutoDiffCostFunction<Se3EdgeFunctor, 6, 7, 7>(
        new Se3EdgeFunctor(tz, qz, sqrtInfo));
  }
  return new Se3EdgeCost(tz, qz, sqrtInfo);
}

}  // namespace rtabmap::optimizer_internal

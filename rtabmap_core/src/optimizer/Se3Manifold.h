#pragma once
// The manifold of an SE3 parameter block double[7] = t (3), q (x y z w) (internal header).
//
// Plus(x, d) = (t + d_t, q * Exp(d_r)): translation in the world frame, rotation perturbed on the
// right (in the body frame). The analytic SE3 residuals return their Jacobian already with
// respect to this 6-vector d, in the first 6 columns of the 7-column block Jacobian Ceres asks
// for (the last column is zero). So PlusJacobian is the selection [I6; 0], and the product Ceres
// forms, J_block * PlusJacobian, is exactly the tangent Jacobian, with no 6x7 * 7x6 product to pay
// (RightMultiplyByPlusJacobian copies the columns). This Jacobian is the derivative of Plus only
// for the residuals written this way: use it with Se3EdgeCost / Se3PriorCost / GravityCost, and
// the true manifold (Ceres's product of Euclidean and quaternion manifolds) with auto-diff.
#include <ceres/manifold.h>

#include <algorithm>

#include "PoseMath.h"

namespace rtabmap::optimizer_internal {

class Se3TangentManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }

  bool Plus(const double* x, const double* delta, double* xPlusDelta) const override {
    for (int i = 0; i < 3; ++i) xPlusDelta[i] = x[i] + delta[i];
    const Eigen::Map<const Eigen::Quaterniond> q(x + 3);
    const Eigen::Quaterniond dq = expSO3(Eigen::Vector3d(delta[3], delta[4], delta[5]));
    Eigen::Map<Eigen::Quaterniond>(xPlusDelta + 3) = (q * dq).normalized();
    return true;
  }

  bool PlusJacobian(const double* /*x*/, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> j(jacobian);
    j.setZero();
    j.topRows<6>().setIdentity();
    return true;
  }

  bool RightMultiplyByPlusJacobian(const double* /*x*/, const int numRows,
                                   const double* ambientMatrix,
                                   double* tangentMatrix) const override {
    for (int r = 0; r < numRows; ++r) {
      std::copy(ambientMatrix + 7 * r, ambientMatrix + 7 * r + 6, tangentMatrix + 6 * r);
    }
    return true;
  }

  bool Minus(const double* y, const double* x, double* yMinusX) const override {
    for (int i = 0; i < 3; ++i) yMinusX[i] = y[i] - x[i];
    const Eigen::Map<const Eigen::Quaterniond> qx(x + 3), qy(y + 3);
    const Eigen::Vector3d w = logSO3(qx.conjugate() * qy);
    yMinusX[3] = w.x(); yMinusX[4] = w.y(); yMinusX[5] = w.z();
    return true;
  }

  bool MinusJacobian(const double* /*x*/, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> j(jacobian);
    j.setZero();
    j.leftCols<6>().setIdentity();
    return true;
  }
};

}  // namespace rtabmap::optimizer_internal

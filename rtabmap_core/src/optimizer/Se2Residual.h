#pragma once
// The residual of a relative SE2 link (internal header; Ceres stays out of public headers).
//
// r = U * e, e = [x, y, theta] of Z^-1 * (Xi^-1 * Xj) (theta wrapped), U' U = Omega (x, y, yaw),
// so |r|^2 is the link's g2o chi2. Poses are double[3] = x, y, theta.
//
// With Ri the rotation of xi, tD = Ri' (tj - ti) and Rz, tz the measurement:
//   e_t = Rz' (tD - tz),  e_theta = wrap(theta_j - theta_i - theta_z)
//   d e_t / d tj = Rz' Ri'          d e_t / d ti = -Rz' Ri'
//   d e_t / d theta_i = Rz' [tD.y, -tD.x]'   (since d Ri'/d theta = -S Ri', S = [0 -1; 1 0])
//   d e_theta / d theta_j = 1,      d e_theta / d theta_i = -1
#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include <cmath>

#include "PoseMath.h"

namespace rtabmap::optimizer_internal {

class Se2EdgeCost final : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  Se2EdgeCost(const Eigen::Vector3d& z, const Eigen::Matrix3d& sqrtInfo)
      : z_(z), u_(sqrtInfo), cz_(std::cos(z[2])), sz_(std::sin(z[2])) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* xi = parameters[0];
    const double* xj = parameters[1];
    const double ci = std::cos(xi[2]), si = std::sin(xi[2]);
    const double dx = xj[0] - xi[0], dy = xj[1] - xi[1];
    const double tdx = ci * dx + si * dy, tdy = -si * dx + ci * dy;
    const double ex = tdx - z_[0], ey = tdy - z_[1];
    const Eigen::Vector3d e(cz_ * ex + sz_ * ey, -sz_ * ex + cz_ * ey,
                            wrapAngle(xj[2] - xi[2] - z_[2]));
    Eigen::Map<Eigen::Vector3d>{residuals} = u_ * e;
    if (!jacobians) return true;

    // Rz' Ri' = R(-(theta_i + theta_z)).
    const double c = ci * cz_ - si * sz_, s = si * cz_ + ci * sz_;
    Eigen::Matrix3d jj;
    jj << c, s, 0.0,
          -s, c, 0.0,
          0.0, 0.0, 1.0;
    if (jacobians[0]) {
      // Rz' [tD.y, -tD.x]
      const double ax = tdy, ay = -tdx;
      Eigen::Matrix3d ji;
      ji << -c, -s, cz_ * ax + sz_ * ay,
            s, -c, -sz_ * ax + cz_ * ay,
            0.0, 0.0, -1.0;
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>{jacobians[0]} = u_ * ji;
    }
    if (jacobians[1]) {
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>{jacobians[1]} = u_ * jj;
    }
    return true;
  }

 private:
  Eigen::Vector3d z_;
  Eigen::Matrix3d u_;
  double cz_, sz_;
};

// The same residual for automatic differentiation.
struct Se2EdgeFunctor {
  Se2EdgeFunctor(const Eigen::Vector3d& z, const Eigen::Matrix3d& sqrtInfo) : z(z), u(sqrtInfo) {}

  template <typename T>
  bool operator()(const T* xi, const T* xj, T* residuals) const {
    using std::cos;
    using std::sin;
    const T ci = cos(xi[2]), si = sin(xi[2]);
    const T dx = xj[0] - xi[0], dy = xj[1] - xi[1];
    const T ex = ci * dx + si * dy - T(z[0]);
    const T ey = -si * dx + ci * dy - T(z[1]);
    const double cz = std::cos(z[2]), sz = std::sin(z[2]);
    T e[3] = {T(cz) * ex + T(sz) * ey, T(-sz) * ex + T(cz) * ey, wrapAngle(xj[2] - xi[2] - T(z[2]))};
    for (int r = 0; r < 3; ++r) {
      residuals[r] = T(0.0);
      for (int k = r; k < 3; ++k) residuals[r] += T(u(r, k)) * e[k];
    }
    return true;
  }

  Eigen::Vector3d z;
  Eigen::Matrix3d u;  // upper triangular
};

inline ceres::CostFunction* makeSe2EdgeCost(const Eigen::Vector3d& z,
                                            const Eigen::Matrix3d& sqrtInfo, bool autoDiff) {
  if (autoDiff) {
    return new ceres::AutoDiffCostFunction<Se2EdgeFunctor, 3, 3, 3>(
        new Se2EdgeFunctor(z, sqrtInfo));
  }
  return new Se2EdgeCost(z, sqrtInfo);
}

}  // namespace rtabmap::optimizer_internal

#pragma once
// Small geometry shared by the residuals, the chi2 and the initialisation (internal header).
//
// Parameter blocks of the optimiser:
//   SE2 pose: double[3] = x, y, theta (theta not wrapped: the residuals wrap the difference).
//   SE3 pose: double[7] = tx, ty, tz, qx, qy, qz, qw (Eigen's quaternion storage order).
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap::optimizer_internal {

constexpr double kPi = 3.14159265358979323846;

// Angle wrapped to (-pi, pi]. Templated for Ceres jets (floor/ceil have zero derivative).
template <typename T>
T wrapAngle(const T& a) {
  using std::ceil;
  return a - T(2.0 * kPi) * ceil((a - T(kPi)) / T(2.0 * kPi));
}

inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0.0, -v.z(), v.y(),
       v.z(), 0.0, -v.x(),
       -v.y(), v.x(), 0.0;
  return s;
}

// x, y, yaw of a transform (its 3DoF part).
inline Eigen::Vector3d toSE2(const Transform& t) { return Eigen::Vector3d(t.x(), t.y(), t.yaw()); }

// Writes a transform into a 7-double SE3 block, and back.
inline void toSE3Block(const Transform& t, double* block) {
  const Eigen::Vector3d p = t.translation();
  const Eigen::Quaterniond q = t.quaternion().normalized();
  block[0] = p.x(); block[1] = p.y(); block[2] = p.z();
  block[3] = q.x(); block[4] = q.y(); block[5] = q.z(); block[6] = q.w();
}
inline Transform fromSE3Block(const double* block) {
  return Transform(block[0], block[1], block[2], block[3], block[4], block[5], block[6]);
}

// Quaternion of the rotation vector w (exact exponential map).
inline Eigen::Quaterniond expSO3(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-12) {
    Eigen::Quaterniond q(1.0, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z());
    return q.normalized();
  }
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, w / angle));
}
// Rotation vector of a unit quaternion (logarithm), angle in [0, pi].
inline Eigen::Vector3d logSO3(Eigen::Quaterniond q) {
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double n = q.vec().norm();
  if (n < 1e-12) return 2.0 * q.vec();
  const double angle = 2.0 * std::atan2(n, q.w());
  return q.vec() * (angle / n);
}

// SE2 error of a relative measurement z (x, y, theta) between poses xi and xj:
// [x, y, theta] of Z^-1 * (Xi^-1 * Xj), theta wrapped.
inline Eigen::Vector3d errorSE2(const double* xi, const double* xj, const Eigen::Vector3d& z) {
  const double ci = std::cos(xi[2]), si = std::sin(xi[2]);
  const double dx = xj[0] - xi[0], dy = xj[1] - xi[1];
  // Xi^-1 * Xj
  const double tx = ci * dx + si * dy, ty = -si * dx + ci * dy;
  const double cz = std::cos(z[2]), sz = std::sin(z[2]);
  const double ex = tx - z[0], ey = ty - z[1];
  return Eigen::Vector3d(cz * ex + sz * ey, -sz * ex + cz * ey, wrapAngle(xj[2] - xi[2] - z[2]));
}

// SE3 error: [t, qvec] of Z^-1 * (Xi^-1 * Xj), with the error quaternion's w >= 0.
inline Eigen::Matrix<double, 6, 1> errorSE3(const Eigen::Vector3d& ti, const Eigen::Quaterniond& qi,
                                            const Eigen::Vector3d& tj, const Eigen::Quaterniond& qj,
                                            const Eigen::Vector3d& tz, const Eigen::Quaterniond& qz) {
  const Eigen::Quaterniond qiInv = qi.conjugate();
  const Eigen::Vector3d tD = qiInv * (tj - ti);
  const Eigen::Quaterniond qD = qiInv * qj;
  const Eigen::Quaterniond qzInv = qz.conjugate();
  Eigen::Quaterniond qE = qzInv * qD;
  if (qE.w() < 0.0) qE.coeffs() = -qE.coeffs();
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = qzInv * (tD - tz);
  e.tail<3>() = qE.vec();
  return e;
}

// Upper-triangular U with U' * U = omega (so |U e|^2 = e' omega e). False if omega is not
// symmetric positive definite.
template <int N>
bool sqrtInformation(const Eigen::Matrix<double, N, N>& omega, Eigen::Matrix<double, N, N>* u) {
  if (!omega.allFinite()) return false;
  const Eigen::Matrix<double, N, N> sym = 0.5 * (omega + omega.transpose());
  Eigen::LLT<Eigen::Matrix<double, N, N>> llt(sym);
  if (llt.info() != Eigen::Success) return false;
  *u = llt.matrixU();
  return u->allFinite() && (u->diagonal().array() > 0.0).all();
}

}  // namespace rtabmap::optimizer_internal

#include "rtabmap_core/geometry/Transform.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {

namespace {

// R = Rz(yaw) * Ry(pitch) * Rx(roll), built from angle-axis products so that the convention is
// spelled out once, in Eigen's own terms.
Eigen::Matrix3d rotationFromEuler(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace

Transform::Transform() : iso_(Eigen::Isometry3d::Identity()), null_(true) {}

Transform::Transform(double x, double y, double z, double roll, double pitch, double yaw)
    : iso_(Eigen::Isometry3d::Identity()), null_(false) {
  iso_.linear() = rotationFromEuler(roll, pitch, yaw);
  iso_.translation() = Eigen::Vector3d(x, y, z);
}

Transform::Transform(double x, double y, double theta) : Transform(x, y, 0.0, 0.0, 0.0, theta) {}

Transform::Transform(double x, double y, double z, double qx, double qy, double qz, double qw)
    : iso_(Eigen::Isometry3d::Identity()), null_(false) {
  Eigen::Quaterniond q(qw, qx, qy, qz);
  const double n = q.norm();
  // A zero quaternion carries no rotation at all: refuse it rather than invent the identity.
  if (!(n > 1e-12) || !std::isfinite(n)) {
    throw std::invalid_argument("Transform: quaternion (" + std::to_string(qx) + ", " +
                                std::to_string(qy) + ", " + std::to_string(qz) + ", " +
                                std::to_string(qw) + ") is zero or not finite: it has no valid norm");
  }
  q.coeffs() /= n;
  iso_.linear() = q.toRotationMatrix();
  iso_.translation() = Eigen::Vector3d(x, y, z);
}

Transform::Transform(double r11, double r12, double r13, double tx, double r21, double r22,
                     double r23, double ty, double r31, double r32, double r33, double tz)
    : iso_(Eigen::Isometry3d::Identity()), null_(false) {
  iso_.matrix().topRows<3>() << r11, r12, r13, tx, r21, r22, r23, ty, r31, r32, r33, tz;
}

Transform::Transform(const Eigen::Isometry3d& iso) : iso_(iso), null_(false) {
  iso_.matrix().row(3) << 0, 0, 0, 1;
}

Transform::Transform(const Eigen::Matrix4d& m) : iso_(Eigen::Isometry3d::Identity()), null_(false) {
  iso_.matrix().topRows<3>() = m.topRows<3>();
}

Transform Transform::Identity() { return Transform(Eigen::Isometry3d::Identity()); }

Transform Transform::fromString(const std::string& text) {
  const std::string quoted = "\"" + text + "\"";
  // Separators: blanks and commas (so "1,2,3" from a launch file works too).
  std::string normalized = text;
  for (char& c : normalized) {
    if (c == ',') c = ' ';
  }
  std::istringstream tokens(normalized);
  std::vector<double> v;
  std::string token;
  while (tokens >> token) {
    if (token == "null" && v.empty()) {
      std::string rest;
      if (tokens >> rest) break;  // "null" followed by anything is malformed
      return Transform();
    }
    // from_chars, unlike strtod, ignores the C locale (a node that called setlocale with a
    // decimal comma would otherwise misread "0.5").
    const char* begin = token.data();
    const char* const last = token.data() + token.size();
    if (token.size() > 1 && *begin == '+') ++begin;
    double value = 0.0;
    const auto [end, ec] = std::from_chars(begin, last, value);
    if (ec != std::errc() || end != last) {
      throw FormatError("Transform::fromString: " + quoted + ": \"" + token +
                        "\" is not a number; expected \"x y z roll pitch yaw\", "
                        "\"x y z qx qy qz qw\", \"x y theta\" or 12 numbers (3x4 row-major)");
    }
    if (!std::isfinite(value)) {
      throw FormatError("Transform::fromString: " + quoted + " contains a non-finite value (" +
                        token + ")");
    }
    v.push_back(value);
  }
  switch (v.size()) {
    case 3:
      return Transform(v[0], v[1], v[2]);
    case 6:
      return Transform(v[0], v[1], v[2], v[3], v[4], v[5]);
    case 7:
      try {
        return Transform(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
      } catch (const std::invalid_argument& e) {
        throw FormatError("Transform::fromString: " + quoted + ": " + e.what());
      }
    case 12:
      return Transform(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9], v[10], v[11]);
    default:
      break;
  }
  throw FormatError("Transform::fromString: " + quoted + " has " + std::to_string(v.size()) +
                    " numbers; expected 3 (x y theta), 6 (x y z roll pitch yaw), 7 (x y z qx qy "
                    "qz qw) or 12 (3x4 row-major), or \"null\"");
}

void Transform::requireNotNull(const char* what) const {
  if (null_) {
    throw std::logic_error(std::string("Transform::") + what +
                           " called on a null transform (no pose); check isNull() first");
  }
}

bool Transform::isIdentity(double epsilon) const {
  if (null_) return false;
  return (iso_.matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff() <= epsilon;
}

bool Transform::isInvalid() const {
  if (null_) return false;
  return !iso_.matrix().allFinite();
}

double Transform::x() const {
  requireNotNull("x");
  return iso_.translation().x();
}
double Transform::y() const {
  requireNotNull("y");
  return iso_.translation().y();
}
double Transform::z() const {
  requireNotNull("z");
  return iso_.translation().z();
}

void Transform::getEulerAngles(double& roll, double& pitch, double& yaw) const {
  requireNotNull("getEulerAngles");
  const Eigen::Matrix3d r = iso_.linear();
  // Inverse of R = Rz(yaw) Ry(pitch) Rx(roll): R(2,0) = -sin(pitch), R(2,1) = cos(pitch) sin(roll),
  // R(2,2) = cos(pitch) cos(roll), R(1,0) = sin(yaw) cos(pitch), R(0,0) = cos(yaw) cos(pitch).
  const double cp = std::hypot(r(0, 0), r(1, 0));
  pitch = std::atan2(-r(2, 0), cp);
  if (cp > 1e-10) {
    roll = std::atan2(r(2, 1), r(2, 2));
    yaw = std::atan2(r(1, 0), r(0, 0));
  } else {
    // Gimbal lock (pitch = +-pi/2): only roll -+ yaw is observable; put it all in roll.
    yaw = 0.0;
    const double sp = r(2, 0) < 0 ? 1.0 : -1.0;
    roll = std::atan2(sp * r(0, 1), r(1, 1));
  }
}

double Transform::roll() const {
  double r, p, y;
  getEulerAngles(r, p, y);
  return r;
}
double Transform::pitch() const {
  double r, p, y;
  getEulerAngles(r, p, y);
  return p;
}
double Transform::yaw() const {
  double r, p, y;
  getEulerAngles(r, p, y);
  return y;
}

void Transform::getTranslationAndEulerAngles(double& x, double& y, double& z, double& roll,
                                             double& pitch, double& yaw) const {
  getEulerAngles(roll, pitch, yaw);
  x = iso_.translation().x();
  y = iso_.translation().y();
  z = iso_.translation().z();
}

Eigen::Vector3d Transform::translation() const {
  requireNotNull("translation");
  return iso_.translation();
}

Eigen::Matrix3d Transform::rotationMatrix() const {
  requireNotNull("rotationMatrix");
  return iso_.linear();
}

Eigen::Quaterniond Transform::quaternion() const {
  requireNotNull("quaternion");
  return Eigen::Quaterniond(iso_.linear()).normalized();
}

const Eigen::Isometry3d& Transform::toEigen() const {
  requireNotNull("toEigen");
  return iso_;
}

Eigen::Matrix4d Transform::toMatrix4d() const {
  requireNotNull("toMatrix4d");
  return iso_.matrix();
}

void Transform::toArray12(double out[12]) const {
  requireNotNull("toArray12");
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) out[r * 4 + c] = iso_.matrix()(r, c);
  }
}

Transform Transform::fromArray12(const double in[12]) {
  return Transform(in[0], in[1], in[2], in[3], in[4], in[5], in[6], in[7], in[8], in[9], in[10],
                   in[11]);
}

Transform Transform::inverse() const {
  requireNotNull("inverse");
  // Rigid inverse (R^T, -R^T t): exact for an orthonormal R, and cheaper than a general inverse.
  Eigen::Isometry3d inv = Eigen::Isometry3d::Identity();
  inv.linear() = iso_.linear().transpose();
  inv.translation() = -(inv.linear() * iso_.translation());
  return Transform(inv);
}

Transform Transform::operator*(const Transform& other) const {
  requireNotNull("operator*");
  other.requireNotNull("operator* (right operand)");
  return Transform(Eigen::Isometry3d(iso_ * other.iso_));
}

Transform& Transform::operator*=(const Transform& other) {
  *this = *this * other;
  return *this;
}

Eigen::Vector3d Transform::operator*(const Eigen::Vector3d& point) const {
  requireNotNull("operator* (point)");
  return iso_ * point;
}

bool Transform::operator==(const Transform& other) const {
  if (null_ || other.null_) return null_ == other.null_;
  return iso_.matrix() == other.iso_.matrix();
}

Transform Transform::to3DoF() const {
  double x, y, z, roll, pitch, yaw;
  getTranslationAndEulerAngles(x, y, z, roll, pitch, yaw);
  return Transform(x, y, yaw);
}

double Transform::getNorm() const {
  requireNotNull("getNorm");
  return iso_.translation().norm();
}

double Transform::getNorm2D() const {
  requireNotNull("getNorm2D");
  return iso_.translation().head<2>().norm();
}

double Transform::getAngle() const {
  requireNotNull("getAngle");
  // 2 atan2(|v|, |w|) is well conditioned near 0 and pi (acos(w) is not), and |w| folds the
  // double cover so the result lies in [0, pi].
  const Eigen::Quaterniond q = quaternion();
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

double Transform::getDistance(const Transform& other) const {
  requireNotNull("getDistance");
  other.requireNotNull("getDistance (argument)");
  return (iso_.translation() - other.iso_.translation()).norm();
}

Transform Transform::interpolate(double t, const Transform& other) const {
  requireNotNull("interpolate");
  other.requireNotNull("interpolate (argument)");
  const Eigen::Quaterniond qa = quaternion();
  const Eigen::Quaterniond qb = other.quaternion();
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = qa.slerp(t, qb).normalized().toRotationMatrix();
  out.translation() = (1.0 - t) * iso_.translation() + t * other.iso_.translation();
  return Transform(out);
}

Transform Transform::normalized() const {
  requireNotNull("normalized");
  Eigen::Isometry3d out = iso_;
  out.linear() = Eigen::Quaterniond(iso_.linear()).normalized().toRotationMatrix();
  return Transform(out);
}

std::string Transform::toString() const {
  if (null_) return "null";
  double x, y, z, roll, pitch, yaw;
  getTranslationAndEulerAngles(x, y, z, roll, pitch, yaw);
  std::ostringstream os;
  os.imbue(std::locale::classic());
  os << std::setprecision(std::numeric_limits<double>::max_digits10) << x << ' ' << y << ' ' << z
     << ' ' << roll << ' ' << pitch << ' ' << yaw;
  return os.str();
}

std::string Transform::prettyPrint() const {
  if (null_) return "null";
  double x, y, z, roll, pitch, yaw;
  getTranslationAndEulerAngles(x, y, z, roll, pitch, yaw);
  // Values that would print as "-0.000" print as "0.000".
  auto clean = [](double v) { return std::abs(v) < 0.0005 ? 0.0 : v; };
  char buf[160];
  std::snprintf(buf, sizeof(buf), "xyz=%.3f,%.3f,%.3f rpy=%.3f,%.3f,%.3f", clean(x), clean(y),
                clean(z), clean(roll), clean(pitch), clean(yaw));
  return buf;
}

std::ostream& operator<<(std::ostream& os, const Transform& t) { return os << t.prettyPrint(); }

}  // namespace rtabmap

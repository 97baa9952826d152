#pragma once
// A rigid transform (rotation + translation) of SE(3), on Eigen, in double precision.
//
// As in the original RTAB-Map, a default-constructed Transform is *null*: it means "no pose"
// (odometry lost, unknown ground truth) and is distinct from the identity. Operations on a
// null transform other than isNull() are programming errors and throw std::logic_error.
//
// Conventions: right-handed; a pose is the transform from the world (or parent) frame to the
// body frame, so `a * b` composes b in a's frame, and the relative motion from pose i to
// pose j is `i.inverse() * j`. Euler angles are roll (x), pitch (y), yaw (z), applied as
// R = Rz(yaw) * Ry(pitch) * Rx(roll).
#include <Eigen/Geometry>

#include <iosfwd>
#include <string>

namespace rtabmap {

class Transform {
 public:
  // Null transform ("no pose"). The predicates isNull(), isIdentity(), isInvalid(), ==, and the
  // printers (toString() -> "null", prettyPrint(), <<) accept it; everything else throws.
  Transform();
  // x, y, z, roll, pitch, yaw (metres, radians).
  Transform(double x, double y, double z, double roll, double pitch, double yaw);
  // 2D pose: x, y, theta (yaw).
  Transform(double x, double y, double theta);
  // Translation and unit quaternion (normalised if it is not quite unit; a zero or non-finite
  // quaternion throws std::invalid_argument).
  Transform(double x, double y, double z, double qx, double qy, double qz, double qw);
  // 3x4 row-major [R | t].
  Transform(double r11, double r12, double r13, double tx,
            double r21, double r22, double r23, double ty,
            double r31, double r32, double r33, double tz);
  explicit Transform(const Eigen::Isometry3d& iso);
  explicit Transform(const Eigen::Matrix4d& m);

  static Transform Identity();
  // Parses "x y z roll pitch yaw", "x y z qx qy qz qw", "x y theta" or 12 numbers (3x4
  // row-major), separated by blanks and/or commas, and "null" (what toString() prints for a
  // null transform). Throws FormatError naming the string on anything else or on NaN/inf.
  static Transform fromString(const std::string& text);

  bool isNull() const { return null_; }
  bool isIdentity(double epsilon = 1e-9) const;
  // True if any element is NaN or infinite (false for a null transform).
  bool isInvalid() const;

  double x() const;
  double y() const;
  double z() const;
  double roll() const;
  double pitch() const;
  double yaw() const;
  // Same as yaw(): the heading of a 2D pose.
  double theta() const { return yaw(); }
  void getEulerAngles(double& roll, double& pitch, double& yaw) const;
  void getTranslationAndEulerAngles(double& x, double& y, double& z, double& roll, double& pitch,
                                    double& yaw) const;

  Eigen::Vector3d translation() const;
  Eigen::Matrix3d rotationMatrix() const;
  Eigen::Quaterniond quaternion() const;
  const Eigen::Isometry3d& toEigen() const;
  Eigen::Matrix4d toMatrix4d() const;
  // 3x4 row-major values, as stored in KITTI pose files and the database.
  void toArray12(double out[12]) const;
  static Transform fromArray12(const double in[12]);

  Transform inverse() const;
  Transform operator*(const Transform& other) const;
  Transform& operator*=(const Transform& other);
  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const;
  bool operator==(const Transform& other) const;
  bool operator!=(const Transform& other) const { return !(*this == other); }

  // Keeps x, y, yaw; zeroes z, roll, pitch (Reg/Force3DoF).
  Transform to3DoF() const;
  // Translation norm, and planar norm.
  double getNorm() const;
  double getNorm2D() const;
  // Angle of the rotation (axis-angle magnitude), in [0, pi].
  double getAngle() const;
  double getDistance(const Transform& other) const;
  // Interpolation between *this (t = 0) and other (t = 1): linear in translation, slerp in
  // rotation.
  Transform interpolate(double t, const Transform& other) const;
  // Re-orthonormalises the rotation (after many compositions in float input).
  Transform normalized() const;

  // "x y z roll pitch yaw" with full precision (round-trips through fromString: the translation
  // exactly, the rotation to a few ulps of the Euler conversion), or "null".
  std::string toString() const;
  // "xyz=1.000,2.000,0.000 rpy=0.000,0.000,1.571" for logs.
  std::string prettyPrint() const;

 private:
  void requireNotNull(const char* what) const;

  Eigen::Isometry3d iso_;
  bool null_;
};

std::ostream& operator<<(std::ostream& os, const Transform& t);

}  // namespace rtabmap

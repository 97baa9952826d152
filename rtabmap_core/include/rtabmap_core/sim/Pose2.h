#pragma once
// A planar pose (x, y, yaw): the ground robot's pose in the world and its wheel odometry. The
// robot never rolls or pitches, so its 3D pose is Transform(x, y, 0, 0, 0, yaw).
#include <cmath>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap::sim {

struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;

  // this * other: `other` expressed in this pose's frame.
  Pose2 operator*(const Pose2& o) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {x + c * o.x - s * o.y, y + s * o.x + c * o.y, normalizeAngle(yaw + o.yaw)};
  }
  Pose2 inverse() const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {-c * x - s * y, s * x - c * y, normalizeAngle(-yaw)};
  }
  Transform toTransform() const { return Transform(x, y, yaw); }

  // Angle in (-pi, pi].
  static double normalizeAngle(double a) {
    a = std::fmod(a, 2.0 * M_PI);
    if (a <= -M_PI) a += 2.0 * M_PI;
    if (a > M_PI) a -= 2.0 * M_PI;
    return a;
  }
};

}  // namespace rtabmap::sim

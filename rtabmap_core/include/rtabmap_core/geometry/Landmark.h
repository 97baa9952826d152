#pragma once
// A landmark seen by a frame (a fiducial marker, or any detection the input brings): which one,
// where it is from the robot, and how sure. Memory turns each into a kLandmark link from the
// node to the landmark's graph node, id -id: every node that sees the same landmark is then
// constrained through it, a loop closure that needs no appearance match (JFR 2019, 3.1).
#include <Eigen/Core>

#include <map>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

struct Landmark {
  int id = 0;           // > 0; its graph node is -id
  float size = 0.0f;    // side length of a square marker (m), 0 = unknown
  Transform pose;       // the landmark's pose in the robot's base frame
  // 6x6 covariance of `pose` (x y z roll pitch yaw); an angular variance >= 9999 means only the
  // position is measured.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();
};

// By landmark id.
using Landmarks = std::map<int, Landmark>;

}  // namespace rtabmap

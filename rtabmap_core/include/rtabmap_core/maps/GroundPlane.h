#pragma once
// The floor in a cloud of the robot's base frame, as a plane: Odom/AlignWithGround starts
// odometry level with it (a hand-held or tilted camera, whose base frame is not level).
#include <Eigen/Core>

#include <optional>

#include "rtabmap_core/maps/Cloud.h"

namespace rtabmap {

struct GroundPlane {
  Eigen::Vector3d normal;  // unit, pointing to the side of the base's origin
  double height = 0.0;     // distance from the base's origin to the plane (> 0: the origin is above)
  int inliers = 0;
};

struct GroundPlaneOptions {
  double maxTilt = 0.8;              // rad: largest angle between the plane's normal and the base's z
  double distance = 0.02;            // m: RANSAC inlier distance
  double minInlierRatio = 0.2;       // of the cloud's points
  int minInliers = 100;
};

// The plane of most inliers (PCL RANSAC, a fixed seed: the same cloud gives the same plane) whose
// normal is within maxTilt of the base's z axis and that lies below the base's origin; nullopt
// when there is none with enough inliers.
std::optional<GroundPlane> findGroundPlane(const Cloud& cloud, const GroundPlaneOptions& options = {});

}  // namespace rtabmap

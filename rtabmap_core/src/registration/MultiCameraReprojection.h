#pragma once
// Multi-camera PnP refinement (internal header): the new base pose that minimises the
// reprojection errors of reference 3D points, each seen in one camera of the rig. Ceres-free:
// the residual is in MultiCameraReprojectionCost.h.
#include <Eigen/Geometry>

#include <vector>

namespace rtabmap::registration_internal {

struct PinholeCamera {
  Eigen::Isometry3d opticalFromBase;
  double fx, fy, cx, cy;
};

// One correspondence: reference point, its pixel in its camera's own image, the camera.
struct CameraObservation {
  Eigen::Vector3d point;
  Eigen::Vector2d pixel;
  int camera = 0;
};

// Levenberg-Marquardt (Ceres) from `motion` (pose of the new base in the reference frame) over
// the observations `inliers`; at most `iterations` steps. Returns the refined motion.
Eigen::Isometry3d refineMultiCameraReprojection(const Eigen::Isometry3d& motion,
                                                const std::vector<CameraObservation>& observations,
                                                const std::vector<int>& inliers,
                                                const std::vector<PinholeCamera>& cameras, int iterations);

}  // namespace rtabmap::registration_internal

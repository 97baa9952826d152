#pragma once
// Motion from correspondences, the second half of visual registration (JFR 2019, 3.1.1
// "Motion Estimation"):
//  - 3D->2D: Perspective-n-Point in RANSAC (OpenCV solvePnPRansac) from 3D points of the
//    reference frame to keypoints of the new image, then refinement on the inliers;
//  - 3D->3D: RANSAC over minimal sets of 3 point pairs, each solved in closed form (Umeyama
//    1991, the least-squares rigid transform), then refinement on the inliers;
//  - the covariance of the result from the median absolute deviation (MAD) of the inliers'
//    3D errors, as the original does: a robust spread that outliers RANSAC let through barely
//    move.
// Frames: reference points are in the reference base frame; new-frame 3D points in the new
// base frame; keypoints in the new (rectified) image whose camera model carries the local
// transform base -> optical. The estimated transform is the new base frame's pose in the
// reference base frame: p_reference = T * p_new.
#include <opencv2/core/types.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

struct PnPOptions {
  float reprojError = 2.0f;  // Vis/PnPReprojError, pixels
  int iterations = 300;      // Vis/Iterations
  int flags = 0;             // Vis/PnPFlags: 0 iterative, 1 EPnP, 2 P3P
  int refineIterations = 1;  // Vis/PnPRefineIterations
  int minInliers = 20;       // Vis/MinInliers
  int shuffleSeed = 0;       // Vis/PnPShuffleSeed: 0 = match order
  bool IsValid(std::string* why = nullptr) const;
};

struct RigidOptions {
  float inlierDistance = 0.1f;  // Vis/InlierDistance, metres
  int iterations = 300;         // Vis/Iterations
  int refineIterations = 5;     // Vis/RefineIterations
  int minInliers = 20;          // Vis/MinInliers
  bool IsValid(std::string* why = nullptr) const;
};

struct MotionEstimate {
  Transform transform;       // null on failure
  std::vector<int> inliers;  // indices into the correspondence arrays
  std::string rejectedMsg;   // why, on failure
  double inlierRmse = 0.0;   // pixels (PnP) or metres (3D-3D)
};

// objectPoints[i] (reference frame) seen at imagePoints[i] (new image): PnP RANSAC, then
// refinement on the inliers. Non-finite points are skipped. A motion guess has no place here:
// RANSAC's minimal solvers start from nothing (the guess serves the matching, before).
MotionEstimate estimateMotion3DTo2D(const std::vector<cv::Point3f>& objectPoints,
                                    const std::vector<cv::Point2f>& imagePoints, const CameraModel& model,
                                    const PnPOptions& options);

// referencePoints[i] (reference frame) and newPoints[i] (new frame) are the same physical point.
// Non-finite pairs are skipped. Deterministic (fixed random seed).
MotionEstimate estimateMotion3DTo3D(const std::vector<cv::Point3f>& referencePoints,
                                    const std::vector<cv::Point3f>& newPoints, const RigidOptions& options);

// Least-squares rigid transform T minimising sum |reference_i - T * new_i|^2 (Umeyama, no
// scale). Null with fewer than 3 pairs or a degenerate (collinear) set.
Transform rigidTransform3D(const std::vector<Eigen::Vector3d>& reference, const std::vector<Eigen::Vector3d>& moved);

// Covariance (x y z roll pitch yaw) of a transform from its inlier 3D correspondences: the
// translational variance is the squared robust standard deviation of the distances
// |reference_i - T * new_i| (1.4826 x their median: the MAD estimate for Gaussian errors around
// 0), the rotational variance the same of the angles between the bearing vectors of each pair
// seen from the reference origin. Floors at 1e-6 (m^2, rad^2) so an exact fit never claims
// certainty. Pairs with a non-finite point are skipped; with fewer than 3 pairs returns the
// identity covariance (unknown).
Eigen::Matrix<double, 6, 6> covarianceFromInliers(const std::vector<cv::Point3f>& referencePoints,
                                                  const std::vector<cv::Point3f>& newPoints,
                                                  const std::vector<int>& inliers, const Transform& transform);

// Same when the new frame has no 3D points (PnP on a monocular image): the errors are the
// reprojection errors of the inliers turned into metres at each point's depth (error x z / f).
Eigen::Matrix<double, 6, 6> covarianceFromReprojection(const std::vector<cv::Point3f>& objectPoints,
                                                       const std::vector<cv::Point2f>& imagePoints,
                                                       const std::vector<int>& inliers, const CameraModel& model,
                                                       const Transform& transform);

}  // namespace rtabmap

#pragma once
// Bundle adjustment (Triggs et al. 2000) with Ceres: the poses of some frames and the 3D points
// they see, refined together to minimise the reprojection errors of the observations, under a
// Huber loss so the few wrong matches RANSAC let through do not drag the solution.
//
// Observations with a depth (RGB-D, stereo) add a disparity-like residual s * (1/z - 1/z_obs),
// so depth constrains the distance of points, which reprojection alone leaves free along the
// viewing rays. Its scale s makes the residual's noise about one pixel, like the reprojection
// residuals beside it:
//  - stereo frames: s = fx * baseline, the residual is the disparity error in pixels;
//  - RGB-D frames: structured-light / ToF depth noise grows as sigma_z = k z^2 (Khoshelham and
//    Elberink 2012 measure k ~ 1.5e-3 to 3e-3 per metre for a Kinect), and the error of 1/z is
//    then sigma_z / z^2 = k whatever the depth: s = 1 / k. (A "virtual baseline" of a few
//    centimetres, fx * 0.075, would weight depth hundreds of times less than it deserves, and
//    a two-view adjustment then trades translation for point depth.)
//
// Frames are given by the pose of their base frame in the world and a camera model whose local
// transform goes base -> optical frame. Fixed frames anchor the gauge; at least one frame must
// be fixed. Points seen by a single frame that is fixed carry no information and stay as they
// are.
#include <opencv2/core/types.hpp>

#include <map>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

struct BundleAdjustmentOptions {
  int iterations = 20;          // Levenberg-Marquardt iterations at most
  double huberPixels = 2.0;     // scale of the Huber loss (Vis/PnPReprojError)
  double depthNoise = 0.01;    // k of RGB-D depth noise sigma_z = k z^2, per metre (0 = ignore depth)
  bool optimizePoints = true;   // false: motion-only (points fixed)
  bool IsValid(std::string* why = nullptr) const;
};

struct BundleAdjustmentFrame {
  Transform pose;     // base frame in the world
  CameraModel model;  // rectified, local transform base -> optical
  bool fixed = false;
  double baseline = 0.0;  // m, > 0 for a stereo frame: its depth residuals are disparity errors
};

struct BundleAdjustmentObservation {
  int frame = 0;
  int point = 0;
  cv::Point2f uv;
  float depth = 0.0f;  // m along the optical axis, 0 = unknown
};

struct BundleAdjustmentSummary {
  bool success = false;
  std::string message;         // why it did not run or failed; Ceres' report otherwise
  int iterations = 0;
  int residualBlocks = 0;
  double initialRmsePx = 0.0;  // reprojection RMSE before and after
  double finalRmsePx = 0.0;
  // Observations whose reprojection error stays above 2 x huberPixels after optimisation: the
  // caller may drop them (bad matches).
  std::vector<size_t> outliers;
};

// Refines `frames` poses (except fixed ones) and `points` in place. Observations naming an
// unknown frame or point, or a point behind its camera, are ignored.
BundleAdjustmentSummary bundleAdjust(std::map<int, BundleAdjustmentFrame>& frames,
                                     std::map<int, cv::Point3f>& points,
                                     const std::vector<BundleAdjustmentObservation>& observations,
                                     const BundleAdjustmentOptions& options = {});

}  // namespace rtabmap

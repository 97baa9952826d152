#pragma once
// How far an estimated trajectory runs from a reference path, when the two cannot be associated
// pose by pose: the reference has no stamps, or poses at other instants (a benchmark pose
// graph such as the Intel lab's intel.g2o, one vertex every ~0.5 m, against a SLAM run's pose at
// every scan). The reference is taken as a path: the polyline through its positions in order.
// The estimate is aligned onto it rigidly by ICP (each estimated position paired with its
// nearest point of the polyline, Umeyama on the pairs, pairs beyond the trimming distance left
// out), then each estimated position's distance to the polyline is the deviation.
//
// What it shows and what it does not: a corridor bowed in one map and straight in the other, a
// doubled pass, a room rotated about its door all put positions off the other path (a
// deviation across the path). An error along the path (the robot placed 1 m further down a
// straight corridor) does not: the position is still on the path. So it is a lower bound of the
// trajectory's error, a check of the map's shape, not an ATE.
#include <cstddef>
#include <vector>

#include "rtabmap_core/eval/Trajectory.h"
#include "rtabmap_core/eval/TrajectoryError.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

struct PathDeviationOptions {
  int maxIterations = 100;
  // ICP stops when an iteration moves the alignment by less than this (metres, radians).
  double convergence = 1e-6;
  // Pairs farther than max(trimDistance, trimQuantile of the current distances) are left out of
  // the next Umeyama fit: a stretch off by more than trimDistance (a wrong loop closure) does not
  // drag the rest, while the quantile keeps half of the pairs when the initial alignment is
  // still far. Below trimDistance the fit is least squares, as the ATE's, so a bend that small is
  // shared between the bent stretch and the rest.
  double trimDistance = 0.5;
  double trimQuantile = 0.5;
  // Initial alignment: the reference's first pose times the inverse of the estimate's first
  // (both start where the robot did), else the identity.
  bool initFromFirstPoses = true;
  // The reference polyline is sampled every `sampleStep` metres to find the nearest segment;
  // the distance to that segment and its two neighbours is computed exactly, so a deviation is
  // within sampleStep / 2 of the true distance to the polyline (exact unless the nearest sample
  // lies on a segment two or more away from the nearest one).
  double sampleStep = 0.02;
};

struct PathDeviationResult {
  size_t referencePoses = 0;  // non-null, in the polyline
  size_t estimatedPoses = 0;  // non-null, each with a deviation
  Transform alignment = Transform::Identity();  // maps the estimate onto the reference
  int iterations = 0;
  bool converged = false;
  double referenceLength = 0.0;  // m, of the polyline
  std::vector<double> deviations;  // m, per non-null estimated pose, in the estimate's order
  std::vector<size_t> estimateIndices;  // index in the estimate of each deviation
  ErrorStats stats;  // of the deviations
  double p90 = 0.0, p99 = 0.0;  // m
};

// Throws FormatError when the reference has fewer than 2 non-null poses (no path) or the
// estimate fewer than 3 (no alignment).
PathDeviationResult computePathDeviation(const Trajectory& reference, const Trajectory& estimate,
                                         const PathDeviationOptions& options = {});

}  // namespace rtabmap

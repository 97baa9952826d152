#pragma once
// Trajectory error metrics against ground truth:
//  - ATE, absolute trajectory error (Sturm et al., IROS 2012): poses associated by stamp, the
//    estimate aligned to the ground truth by the least-squares rigid (or similarity) transform
//    of Horn / Umeyama, then statistics of the position differences.
//  - RPE, relative pose error (same paper): error of the motion over a fixed number of frames
//    or a fixed travelled distance, translational and rotational.
//  - KITTI odometry error (Geiger et al., CVPR 2012, the devkit's evaluate_odometry): average
//    relative translational (%) and rotational (deg/m) error over all sub-sequences of 100,
//    200, ..., 800 m starting every 10 frames.
// Rotational errors are in degrees throughout. Standard deviations are population ones (over
// N, as numpy.std).
#include <cstddef>
#include <utility>
#include <vector>

#include "rtabmap_core/eval/Trajectory.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

struct ErrorStats {
  size_t count = 0;
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;  // population standard deviation
  double min = 0.0;
  double max = 0.0;
};
// Statistics of a list of errors (all zero for an empty list).
ErrorStats computeErrorStats(const std::vector<double>& values);
// The p-th quantile (p in 0..1) by nearest rank: the sorted values' element round(p (n - 1));
// 0 for an empty list.
double percentile(std::vector<double> values, double p);

// Pairs (index in a, index in b) of poses whose stamps differ by at most maxDifference, each
// pose used once, the closest candidate pairs taken first (as the TUM benchmark's
// associate.py); returned in the time order of a's poses. Null poses are never associated.
// Indices refer to the trajectories as given (sorted or not).
std::vector<std::pair<size_t, size_t>> associateByStamp(const Trajectory& a, const Trajectory& b,
                                                        double maxDifference);

enum class TrajectoryAlignment {
  kNone,  // compare the poses as they are
  kSE3,   // rigid: rotation and translation
  kSim3,  // similarity: also a scale (monocular estimates)
};

// Least-squares alignment of point set `source` onto `target` (Umeyama 1991): the transform T
// (and scale s when withScale) minimising sum |target_i - (s R source_i + t)|^2. Needs at least
// 3 points for a unique answer (fewer: FormatError). Returns T with its rotation unscaled; the
// scale goes to *scale (1 without scaling).
Transform alignPoints(const std::vector<Eigen::Vector3d>& source,
                      const std::vector<Eigen::Vector3d>& target, bool withScale,
                      double* scale = nullptr);

struct AteOptions {
  double maxTimeDifference = 0.02;  // seconds, for the stamp association
  TrajectoryAlignment alignment = TrajectoryAlignment::kSE3;
};

struct AteResult {
  size_t groundTruthPoses = 0;
  size_t estimatedPoses = 0;
  std::vector<std::pair<size_t, size_t>> pairs;  // (gt index, est index), in time order
  Transform alignment = Transform::Identity();  // maps the estimate into the ground-truth frame
  double scale = 1.0;                            // kSim3 only
  std::vector<double> errors;                    // metres, one per pair
  ErrorStats translation;                        // metres
};
// Throws FormatError when fewer poses than the alignment needs are associated (1 without
// alignment, 3 with), saying how many were and the stamp ranges of both trajectories.
AteResult computeAte(const Trajectory& groundTruth, const Trajectory& estimate,
                     const AteOptions& options = {});
// The estimate after the alignment of an ATE result (scale applied to positions).
Trajectory applyAlignment(const Trajectory& estimate, const Transform& alignment, double scale = 1.0);

struct RpeOptions {
  double maxTimeDifference = 0.02;
  enum class Unit { kFrames, kMetres } unit = Unit::kFrames;
  // kFrames: compare pose i with pose i + delta (of the associated poses, delta >= 1 integer);
  // kMetres: with the first pose at least delta metres further along the ground-truth path.
  double delta = 1.0;
};

struct RpeResult {
  size_t associated = 0;     // associated poses
  ErrorStats translation;    // metres
  ErrorStats rotation;       // degrees
};
// Error of each pair: E = (gt_i^-1 gt_j)^-1 (est_i^-1 est_j), translation |t(E)|, rotation
// angle(E). Throws FormatError when no pair can be formed.
RpeResult computeRpe(const Trajectory& groundTruth, const Trajectory& estimate,
                     const RpeOptions& options = {});

struct KittiOptions {
  std::vector<double> lengths = {100, 200, 300, 400, 500, 600, 700, 800};  // metres
  size_t stepSize = 10;  // first frames of the sub-sequences: every stepSize frames
};

struct KittiLengthError {
  double length = 0.0;
  size_t segments = 0;
  double translationPercent = 0.0;    // mean |t error| / length * 100
  double rotationDegPerMetre = 0.0;   // mean angle error / length, degrees per metre
};

struct KittiResult {
  size_t frames = 0;
  size_t segments = 0;  // sub-sequences evaluated over all lengths
  double translationPercent = 0.0;   // average over every segment, as the devkit reports
  double rotationDegPerMetre = 0.0;
  std::vector<KittiLengthError> perLength;  // lengths with at least one segment
};
// groundTruth[i] and estimate[i] are the poses of the same frame (equal sizes, else
// FormatError). No alignment: only relative motions are compared. A sub-sequence starts at
// frame f and ends at the first frame whose ground-truth path distance from f exceeds the
// length; errors are those of (est_f^-1 est_l)^-1 (gt_f^-1 gt_l), divided by the length.
// Throws FormatError when the ground truth is shorter than the smallest length.
KittiResult computeKittiError(const std::vector<Transform>& groundTruth,
                              const std::vector<Transform>& estimate,
                              const KittiOptions& options = {});

}  // namespace rtabmap

#pragma once
// Rtabmap/ComputeRMSE: when the input carries ground truth (datasets, the simulator), each update
// says how far the map is from it: the optimised poses of the local map's nodes that have a
// ground-truth pose, rigidly aligned to them (Umeyama), then the statistics of the position
// errors and of the orientation errors (what rtabmap-eval's ATE measures, online). Private to
// the slam area.
#include <map>
#include <optional>

#include "rtabmap_core/eval/TrajectoryError.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

struct GroundTruthErrors {
  ErrorStats translational;  // metres
  ErrorStats rotational;     // degrees
};

// Over the ids in both maps; nullopt with fewer than 3 of them (no unique alignment).
std::optional<GroundTruthErrors> groundTruthErrors(const std::map<int, Transform>& poses,
                                                   const std::map<int, Transform>& groundTruth);

}  // namespace rtabmap

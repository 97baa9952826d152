#pragma once
// One scan from several: each scan (with its own sensor -> base local transform) moved by the
// pose of its node in a common frame, concatenated. The one-to-many scan matching of proximity
// detection matches a new scan against a piece of an earlier trajectory this way.
#include <utility>
#include <vector>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

// Parts whose format differs from the first part's are skipped. The result has the first
// part's format, an identity local transform, the sum of the parts' maxPoints and no beam
// geometry. A 2D format stays 2D: the poses are assumed planar (their z is dropped).
LaserScan mergeScans(const std::vector<std::pair<LaserScan, Transform>>& parts);

}  // namespace rtabmap

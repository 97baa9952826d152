#pragma once
// The landmark constraints of a new node: one kLandmark link from the node to each landmark it
// sees (graph node -id), holding the landmark's pose in the node's base frame and the inverse of
// its covariance. The optimiser places each landmark from the links of every node that saw it,
// so two nodes seeing the same marker are tied through it, whatever their odometry says.
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Landmark.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap::memory {

// Links of node `id` to `landmarks`. A landmark with an id <= 0, a null or non-finite pose, or a
// covariance that is not finite and positive on its diagonal is left out (its reason in `why`,
// one line per landmark, when given).
std::vector<Link> landmarkLinksOf(int id, const Landmarks& landmarks, std::vector<std::string>* why = nullptr);

}  // namespace rtabmap::memory

#pragma once
// RGBD/LocalBundleOnLoopClosure (the original's Memory::computeTransform): a loop closure found by
// appearance is registered against the old node's local feature map, its words and those of its
// neighbours in the graph, all in the old node's frame, rather than against its words alone. The
// new view then matches the features the neighbours saw and the old node missed, and the
// correspondences come from many views of the place. The new node's pose is then refined by
// bundle adjustment against the old node's own observations of the matched points (the old node
// fixed, the points free; the neighbours only serve the matching, see registerToLocalMap), and
// the correspondences the adjustment leaves far from their observations are dropped from the
// inliers. (The original adjusts over every view, the neighbours fixed at their links: measured
// worse here, see registerToLocalMap.) Private to the slam area.
#include <map>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/registration/BundleAdjustment.h"
#include "rtabmap_core/registration/RegistrationInfo.h"
#include "rtabmap_core/registration/RegistrationVis.h"

namespace rtabmap {

class Signature;
namespace memory {
class Memory;
}

// The words (with 3D and descriptor, seen once in their node) of a node and of its neighbours
// in memory, as a feature map in the node's base frame. A word seen by several of them takes the
// node's own point when it has one, else the first neighbour's (by id).
struct LocalFeatureMap {
  int center = 0;
  VisualFrame frame;                             // points3D, descriptors, ids = word ids
  std::map<int, BundleAdjustmentFrame> views;    // node id -> pose in the center's frame (its links), camera
  std::vector<BundleAdjustmentObservation> observations;  // the center's: frame = its id, point = word id
  std::string problem;                           // non-empty: no map, and why
};

// The local feature map around `center`: its words and those of the nodes it has a neighbour
// link to (in memory, with words), placed by those links. A problem when `center` or no
// neighbour has such words, or a node has several cameras (the adjustment knows one per view).
LocalFeatureMap localFeatureMap(const memory::Memory& memory, int center);

// Pose of `current`'s base in the map center's base (the loop-closure link current -> center),
// registered by `visual` from `current`'s frame to the map (Reg/RepeatOnce: again from its own
// first estimate), then refined by bundle adjustment. `guess` current -> center, null = none.
// info->covariance is the link's (current -> center). Null with info->rejectedMsg on failure.
Transform registerToLocalMap(const LocalFeatureMap& map, Signature& current, const RegistrationVis& visual,
                             bool repeatOnce, const Transform& guess, RegistrationInfo* info);

}  // namespace rtabmap

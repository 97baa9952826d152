#pragma once
// Localization mode's odometry cache (RGBD/MaxOdomCacheSize, as the original's): the last
// frames of the localization session, chained by their odometry, with the localization links
// found at them. A new localization link is accepted only if the cached frames, their odometry
// and every cached link can hold it together: the frames and the map nodes are optimised (map
// nodes held by strong priors: the map does not move in localization mode) and no link may be
// off by more than RGBD/OptimizeMaxError of its standard deviations afterwards.
//
// Why: in localization mode a link is trusted with nothing else to contradict it. Proximity
// detection searches around where the robot is *assumed* to be; when that is wrong (restarted
// elsewhere than where the last session ended, no initial pose), ICP can lock on look-alike
// walls there, and the robot "localises" metres away from the truth. Two localizations at two
// different times, joined by odometry, must agree before map -> odom moves: the first link is
// kept, not applied, until a second one confirms it. Once localised, each new link is checked
// against the recent ones, so a single wrong match cannot teleport the robot, and map -> odom
// comes from the optimised pose of the newest frame (smoothed by all the cached links).
//
// A loop closure (appearance) or a marker seen again (kLandmark, to the map node that saw it)
// that disagrees with cached proximity links is tried again without them; if it then fits, the
// proximity links were the wrong ones and leave the cache.
#include <deque>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"
#include "rtabmap_core/optimizer/Optimizer.h"

namespace rtabmap {

struct OdometryCacheOptions {
  int maxSize = 10;             // RGBD/MaxOdomCacheSize: frames kept; 0 = no verification
  double maxErrorRatio = 3.0;   // RGBD/OptimizeMaxError: 0 = no verification
  OptimizerOptions optimizer;   // the map's optimiser settings (Reg/Force3DoF included)

  bool enabled() const { return maxSize > 0 && maxErrorRatio > 0.0; }
};

// A localization link of a cached frame: to a map node whose pose (map frame) is known.
struct CachedLink {
  Link link;           // from the frame (its id is ignored) to the map node
  Transform mapPose;   // pose of link.to() in the map
};

struct OdometryCacheVerdict {
  bool accepted = false;    // the link fits the cached ones (or nothing to check it against)
  bool confirmed = false;   // accepted and an earlier frame also localised: apply it
  Transform pose;           // accepted: the newest frame in the map (optimised when checked)
  double worstRatio = 0.0;  // largest link error, in standard deviations, after optimisation
  int proximityDropped = 0; // cached proximity links a fitting loop closure showed wrong
  std::string why;          // refused: which link disagreed; accepted unconfirmed: waiting
};

class OdometryCache {
 public:
  explicit OdometryCache(const OdometryCacheOptions& options = OdometryCacheOptions());

  void clear();
  // A new frame at this odometry pose; `motion` is the information of the odometry motion from
  // the previous frame (ignored for the first). The oldest frames beyond RGBD/MaxOdomCacheSize
  // leave, with their links.
  void addFrame(const Transform& odom, const Link::InfMatrix& motion);
  // Checks a localization link of the newest frame (addFrame first). An accepted link is kept in
  // the cache; a refused one is not.
  OdometryCacheVerdict verify(const CachedLink& candidate);

  size_t frames() const { return frames_.size(); }
  size_t links() const;  // localization links cached

 private:
  struct Frame {
    Transform odom;
    Link::InfMatrix motion;          // from the previous frame
    std::vector<CachedLink> links;
  };
  struct Check {
    bool ok = false;
    Transform newest;
    double worstRatio = 0.0;
    std::string why;
  };
  // Optimises the frames, their links (without proximity ones if asked) and the candidate.
  Check check(const CachedLink& candidate, bool withoutProximity) const;
  bool earlierFrameLocalized() const;
  void dropProximityLinks(int* dropped);

  OdometryCacheOptions options_;
  std::deque<Frame> frames_;
};

}  // namespace rtabmap

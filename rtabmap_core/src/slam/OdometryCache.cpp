#include "OdometryCache.h"

#include <algorithm>
#include <map>
#include <sstream>

#include "rtabmap_core/optimizer/LinkErrors.h"

namespace rtabmap {
namespace {

// Map nodes are held where the map has them by a prior of 1 mm and 1 mrad standard deviation,
// far stiffer than any registration: the frames move, not the map.
const Link::InfMatrix kMapPriorInformation = Link::InfMatrix::Identity() * 1e6;

// "frame 3 -> node 120": cached frames by their index, map nodes by their id.
std::string linkName(int from, int to, int firstFrameId) {
  const auto end = [firstFrameId](int id) {
    return id >= firstFrameId ? "frame " + std::to_string(id - firstFrameId) : "node " + std::to_string(id);
  };
  return end(from) + " -> " + end(to);
}

}  // namespace

OdometryCache::OdometryCache(const OdometryCacheOptions& options) : options_(options) {}

void OdometryCache::clear() { frames_.clear(); }

void OdometryCache::addFrame(const Transform& odom, const Link::InfMatrix& motion) {
  if (!options_.enabled()) return;
  frames_.push_back({odom, motion, {}});
  while (static_cast<int>(frames_.size()) > options_.maxSize) frames_.pop_front();
}

size_t OdometryCache::links() const {
  size_t n = 0;
  for (const Frame& f : frames_) n += f.links.size();
  return n;
}

bool OdometryCache::earlierFrameLocalized() const {
  for (size_t i = 0; i + 1 < frames_.size(); ++i) {
    if (!frames_[i].links.empty()) return true;
  }
  return false;
}

void OdometryCache::dropProximityLinks(int* dropped) {
  for (Frame& f : frames_) {
    const auto proximity = [](const CachedLink& c) { return c.link.type() == Link::kLocalSpaceClosure; };
    const auto it = std::remove_if(f.links.begin(), f.links.end(), proximity);
    *dropped += static_cast<int>(f.links.end() - it);
    f.links.erase(it, f.links.end());
  }
}

OdometryCache::Check OdometryCache::check(const CachedLink& candidate, bool withoutProximity) const {
  Check result;
  // Graph ids: the map nodes keep theirs; frame i is firstFrame + i, above every map node.
  int firstFrame = candidate.link.to() + 1;
  for (const Frame& f : frames_) {
    for (const CachedLink& c : f.links) firstFrame = std::max(firstFrame, c.link.to() + 1);
  }
  const int newest = firstFrame + static_cast<int>(frames_.size()) - 1;
  // The first estimate: every frame where the candidate puts the newest one, moved by odometry.
  const Transform correction =
      candidate.mapPose * candidate.link.transform().inverse() * frames_.back().odom.inverse();

  std::map<int, Transform> poses;
  std::multimap<int, Link> links;
  const auto addLocalization = [&](int frameId, const CachedLink& c) {
    links.emplace(frameId, Link(frameId, c.link.to(), c.link.type(), c.link.transform(), c.link.infMatrix()));
    if (poses.emplace(c.link.to(), c.mapPose).second) {
      links.emplace(c.link.to(), Link(c.link.to(), c.link.to(), Link::kPosePrior, c.mapPose, kMapPriorInformation));
    }
  };
  for (size_t i = 0; i < frames_.size(); ++i) {
    const int id = firstFrame + static_cast<int>(i);
    poses.emplace(id, correction * frames_[i].odom);
    if (i > 0) {
      links.emplace(id - 1, Link(id - 1, id, Link::kNeighbor, frames_[i - 1].odom.inverse() * frames_[i].odom,
                                 frames_[i].motion));
    }
    for (const CachedLink& c : frames_[i].links) {
      if (withoutProximity && c.link.type() == Link::kLocalSpaceClosure) continue;
      addLocalization(id, c);
    }
  }
  addLocalization(newest, candidate);

  OptimizerOptions o = options_.optimizer;
  o.priorsIgnored = false;  // the priors hold the map
  o.robust = false;         // a robust loss would hide the very disagreement looked for
  o.initialization = GraphInitialization::kInputPoses;
  OptimizerSummary summary;
  const std::map<int, Transform> optimised = optimizeGraph(o, poses, links, &summary, newest);
  if (!summary.success || !optimised.count(newest)) {
    result.why = "the optimisation of the cached frames failed: " + summary.why;
    return result;
  }
  // Every link counts, odometry included: a wrong localization is satisfied by the optimiser,
  // and it is the odometry between the frames that bends.
  const std::vector<graph::LinkError> errors = graph::computeLinkErrors(optimised, links, o.force3DoF, false);
  const graph::LinkError* worst = nullptr;
  for (const graph::LinkError& e : errors) {
    if (!worst || e.worstRatio() > worst->worstRatio()) worst = &e;
  }
  result.worstRatio = worst ? worst->worstRatio() : 0.0;
  result.newest = optimised.at(newest);
  result.ok = result.worstRatio <= options_.maxErrorRatio;
  if (!result.ok) {
    std::ostringstream s;
    s << "with the " << frames_.size() << " cached frames, link "
      << linkName(worst->from, worst->to, firstFrame) << " is off by "
      << worst->translationalError << " m / " << worst->angularError << " rad, " << result.worstRatio
      << " standard deviations (RGBD/OptimizeMaxError " << options_.maxErrorRatio << ")";
    result.why = s.str();
  }
  return result;
}

OdometryCacheVerdict OdometryCache::verify(const CachedLink& candidate) {
  OdometryCacheVerdict v;
  const Transform direct = candidate.mapPose * candidate.link.transform().inverse();
  if (!options_.enabled()) {
    v.accepted = v.confirmed = true;
    v.pose = direct;
    return v;
  }
  if (frames_.empty()) {
    v.why = "no frame cached (addFrame not called)";
    return v;
  }
  if (links() == 0) {
    // Nothing to check it against: kept, waiting for a second one.
    frames_.back().links.push_back(candidate);
    v.accepted = true;
    v.pose = direct;
    v.why = "waiting for a localization at a later frame to confirm it (RGBD/MaxOdomCacheSize)";
    return v;
  }
  Check c = check(candidate, false);
  if (!c.ok && (candidate.link.type() == Link::kGlobalClosure || candidate.link.type() == Link::kLandmark)) {
    // Appearance (or a marker, whose id is unambiguous) against proximity: if the loop closure
    // fits without the cached proximity links, they were the wrong ones (proximity searches
    // around a belief that may be wrong).
    const Check without = check(candidate, true);
    if (without.ok) {
      dropProximityLinks(&v.proximityDropped);
      c = without;
    }
  }
  v.worstRatio = c.worstRatio;
  if (!c.ok) {
    v.why = c.why;
    return v;
  }
  frames_.back().links.push_back(candidate);
  v.accepted = true;
  v.pose = c.newest;
  v.confirmed = earlierFrameLocalized();
  if (!v.confirmed) v.why = "waiting for a localization at a later frame to confirm it (RGBD/MaxOdomCacheSize)";
  return v;
}

}  // namespace rtabmap

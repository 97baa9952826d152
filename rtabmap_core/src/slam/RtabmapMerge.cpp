// Multi-session merges put to the vote (MergeArbiter.h): the links that joined the current map
// to earlier ones, the closures refused for their jump, and the merge redone when they agree.
#include <sstream>

#include "RtabmapImpl.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap {

void Rtabmap::Impl::recordMergeLinks(const std::vector<Link>& kept) {
  for (const Link& l : kept) {
    if (l.to() < 0) continue;  // a landmark joins no maps (RtabmapLandmarks.cpp)
    const int a = graph.mapOf(l.from()), b = graph.mapOf(l.to());
    if (a == b || (a != mapId && b != mapId)) continue;
    mergeLinks.push_back(l);
    if (l.type() == Link::kUserClosure) mergeArbiter.settle();
    if (l.type() == Link::kGlobalClosure) mergeArbiter.support();
  }
}

std::vector<Link> Rtabmap::Impl::arbitrateMerge(int newId, const std::optional<Link>& refused) {
  if (!refused || mergeLinks.empty()) return {};
  const Link& l = *refused;
  if (graph.mapOf(l.to()) == mapId) return {};  // within the current map: not about the merge
  const Transform here = graph.pose(l.from()), there = graph.pose(l.to());
  if (here.isNull() || there.isNull()) return {};
  mergeArbiter.dissent(l, here, there * l.transform().inverse());
  const std::optional<Remerge> r = mergeArbiter.decide(newId);
  return r ? remerge(*r) : std::vector<Link>{};
}

// Undoes every link this process added between the current map and the others (proximity links
// found where the wrong merge put the robot included), moves the current map by the agreeing
// closures' correction, and links it through them. The caller optimises: the graph still has
// the last word (RGBD/OptimizeMaxError), and a refused remerge leaves the map on its own until
// the next closure, which is better than a map merged metres off.
std::vector<Link> Rtabmap::Impl::remerge(const Remerge& r) {
  memory::Memory& memory = detector->memory();
  for (const Link& l : mergeLinks) {
    if (!memory.removeLink(l.from(), l.to(), l.type()) && db) db->removeLink(l.from(), l.to(), l.type());
    detector->linksChanged({l.from(), l.to()});
    graph.unmergeMaps(graph.mapOf(l.from()), graph.mapOf(l.to()));
  }
  std::map<int, Transform> moved;
  for (const auto& [id, pose] : graph.poses()) {
    if (graph.mapOf(id) == mapId) moved.emplace(id, r.correction * pose);
  }
  graph.updatePoses(moved);
  std::vector<Link> added;
  std::ostringstream ids;
  for (const Link& l : r.links) {
    if (!memory.inRam(l.from()) || !memory.inRam(l.to())) continue;
    memory.addLink(l);
    detector->linksChanged({l.from(), l.to()});
    graph.mergeMaps(graph.mapOf(l.from()), graph.mapOf(l.to()));
    added.push_back(l);
    ids << " " << l.from() << "->" << l.to();
  }
  RTABMAP_WARN("map " << mapId << " was merged at the wrong place: " << r.links.size()
                      << " refused loop closures agree elsewhere against " << mergeArbiter.supportCount()
                      << " for the merge; " << mergeLinks.size() << " link(s) undone, the map moved by "
                      << r.correction.getNorm() << " m and merged again through" << ids.str());
  mergeLinks.clear();
  mergeArbiter.reset();
  ++summary.remerges;
  return added;
}

}  // namespace rtabmap

// Rtabmap queries and edits for the ROS interface (Rtabmap.h, "Queries and edits"): paths
// planned without becoming the goal, a node's data from RAM or the database, and links given
// by the user.
#include <algorithm>

#include "RtabmapImpl.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/db/Types.h"
#include "rtabmap_core/optimizer/Graph.h"

namespace rtabmap {
namespace {

// Keeps only the asked parts of a node's sensor data (raw and compressed alike); the
// calibration, GPS, IMU and odometry stay: they are small and describe the node.
SensorData keepParts(const SensorData& in, const NodeDataParts& parts) {
  SensorData out = in;
  if (!parts.images) {
    // setRGBDImage / setStereoImage with no image keep the models and drop both forms.
    if (in.isStereo()) {
      out.setStereoImage(cv::Mat(), cv::Mat(), in.stereoCameraModels());
    } else {
      out.setRGBDImage(cv::Mat(), cv::Mat(), in.cameraModels());
    }
  }
  if (!parts.scan) out.setLaserScan(LaserScan());
  if (!parts.userData) out.setUserData(cv::Mat());
  if (!parts.grid) out.setLocalGrid(LocalGrid());
  out.setCompressed(parts.images ? in.imageCompressed() : Bytes(), parts.images ? in.depthOrRightCompressed() : Bytes(),
                    parts.scan ? in.laserScanCompressed() : Bytes(), parts.userData ? in.userDataCompressed() : Bytes());
  if (!parts.scan) out.setLaserScanInfo(SensorData::ScanInfo());
  return out;
}

std::vector<std::pair<int, Transform>> noPath(std::string* why, const std::string& reason) {
  if (why) *why = reason;
  return {};
}

// The same inputs setGoal() gives the planner: every node of the current referential and every
// link of the map, database and RAM, then a planner of its own so the active plan is untouched.
// (A template only because Rtabmap::Impl is private to Rtabmap: Impl is deduced, not named.)
template <class Impl>
std::vector<std::pair<int, Transform>> planWith(const Impl& impl, const PlanGoal& goal, std::string* why) {
  if (!impl.initialized) return noPath(why, "no map: init() was not called");
  if (impl.lastNodeId == 0 && impl.currentPose.isNull()) return noPath(why, "the robot is not in the map yet (no update)");
  // loadAllLinks() waits for the queued writes itself (and does not throw if the writer has
  // stopped, e.g. disk full: planning on what is saved and in RAM still works).
  std::multimap<int, Link> links;
  if (impl.db) links = impl.db->loadAllLinks(false);
  for (const auto& [from, link] : impl.ramLinks(impl.ramPosesOfGroup())) links.emplace(from, link);
  PathPlanner planner(impl.planner.options());
  const PlanResult r = planner.plan(goal, impl.graph.posesOfGroup(impl.mapId), graph::filterDuplicateLinks(links),
                                    impl.lastNodeId, impl.currentPose);
  if (!r.found) return noPath(why, "no path to the goal: " + r.why);
  return r.path;
}

}  // namespace

std::vector<std::pair<int, Transform>> Rtabmap::planPath(int nodeId, std::string* why) const {
  return planWith(*impl_, PlanGoal::node(nodeId), why);
}

std::vector<std::pair<int, Transform>> Rtabmap::planPath(const Transform& pose, std::string* why) const {
  if (pose.isNull() || pose.isInvalid()) return noPath(why, "the goal pose is null or not finite");
  return planWith(*impl_, PlanGoal::at(pose), why);
}

std::optional<Signature> Rtabmap::node(int id, const NodeDataParts& parts) const {
  if (!impl_->detector) return std::nullopt;
  if (const Signature* s = impl_->detector->memory().signature(id)) {
    Signature copy = *s;
    copy.setSensorData(keepParts(s->sensorData(), parts));
    return copy;
  }
  if (!impl_->db) return std::nullopt;
  db::LoadOptions options;
  options.image = options.depthOrRight = parts.images;
  options.scan = parts.scan;
  options.grid = parts.grid;
  options.userData = parts.userData;
  return impl_->db->loadNode(id, options);
}

std::vector<int> Rtabmap::allNodeIds() const {
  std::vector<int> ids = workingMemory();
  if (impl_->db) {
    const std::vector<int> saved = impl_->db->nodeIds();
    ids.insert(ids.end(), saved.begin(), saved.end());
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

bool Rtabmap::addLink(const Link& link) {
  Impl& m = *impl_;
  m.rejection.clear();
  const auto refuseLink = [&m](const std::string& why) {
    m.rejection = why;
    RTABMAP_WARN("link refused: " << why);
    return false;
  };
  if (!m.detector) return refuseLink("no map: init() was not called");
  if (!m.options.incremental) return refuseLink("localization mode: the map is not modified");
  if (link.from() == link.to()) return refuseLink("a link needs two different nodes");
  if (link.transform().isNull() || link.transform().isInvalid()) return refuseLink("the link's transform is null or not finite");
  for (int id : {link.from(), link.to()}) {
    if (!m.graph.contains(id) || m.graph.pose(id).isNull()) return refuseLink("node " + std::to_string(id) + " is not in the map");
  }
  memory::Memory& memory = m.detector->memory();
  std::vector<int> inLtm;
  for (int id : {link.from(), link.to()}) {
    if (!memory.inRam(id)) inLtm.push_back(id);
  }
  // Both ends must be in RAM to carry the link and to be optimised with it.
  if (!inLtm.empty() && m.db) memory.retrieveIds(inLtm);
  if (!memory.inRam(link.from()) || !memory.inRam(link.to())) return refuseLink("a node of the link could not be loaded");
  const Link user(link.from(), link.to(), Link::kUserClosure, link.transform(), link.infMatrix());
  memory.addLink(user);
  m.detector->linksChanged({user.from(), user.to()});
  m.graph.mergeMaps(m.graph.mapOf(user.from()), m.graph.mapOf(user.to()));
  if (m.lastNodeId == 0 || !m.options.metric) return true;
  // Re-optimised now rather than at the next update: the caller learns whether the graph
  // accepted the link, and map -> odom follows at once.
  const std::vector<Link> kept = m.optimizeLocalMap(m.lastNodeId, {user});
  if (kept.empty()) return refuseLink("the graph disagrees with the link (" + std::string(Parameters::kRGBDOptimizeMaxError()) + ")");
  m.recordMergeLinks(kept);
  const Transform pose = m.graph.pose(m.lastNodeId);
  if (!pose.isNull() && !m.lastNodeOdom.isNull()) {
    m.mapCorrection = pose * m.lastNodeOdom.inverse();
    m.currentPose = m.mapCorrection * m.lastOdom;
  }
  if (m.grid) m.grid->update(m.graph.posesOfGroup(m.mapId));  // no new node: never deferred
  return true;
}

}  // namespace rtabmap

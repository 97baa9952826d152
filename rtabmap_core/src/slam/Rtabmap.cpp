#include "rtabmap_core/slam/Rtabmap.h"

#include "RtabmapImpl.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/optimizer/Graph.h"

namespace rtabmap {

Rtabmap::Rtabmap() : impl_(std::make_unique<Impl>()) {}

Rtabmap::~Rtabmap() {
  try {
    close();
  } catch (const std::exception& e) {
    RTABMAP_ERROR("closing the map: " << e.what());
  }
}

void Rtabmap::init(const ParametersMap& parameters, const std::string& databasePath) {
  if (impl_->initialized) close();
  impl_ = std::make_unique<Impl>();
  impl_->open(parameters, databasePath);
  if (!impl_->options.incremental) {
    // Localization works in the referential of the newest node: the database's last map id
    // can be a session that added no node (one closed at once, a backup).
    const int newest = impl_->newestMapId();
    if (newest >= 0) impl_->mapId = newest;
  }
}

void Rtabmap::close() { impl_->close(); }

bool Rtabmap::isInitialized() const { return impl_->initialized; }

bool Rtabmap::process(const SensorData& data, const Transform& odomPose, const Eigen::Matrix<double, 6, 6>& odomCovariance) {
  return impl_->process(data, odomPose, odomCovariance);
}

bool Rtabmap::process(const SensorData& data) { return process(data, data.odomPose(), data.odomCovariance()); }

const std::string& Rtabmap::lastRejection() const { return impl_->rejection; }
const Statistics& Rtabmap::statistics() const { return impl_->stats; }
SlamSummary Rtabmap::summary() const { return impl_->summary; }
Transform Rtabmap::mapCorrection() const { return impl_->mapCorrection; }
Transform Rtabmap::currentPose() const { return impl_->currentPose; }
int Rtabmap::mapId() const { return impl_->mapId; }
int Rtabmap::lastNodeId() const { return impl_->lastNodeId; }
int Rtabmap::newestNodeId() const { return impl_->lastChainId; }

std::map<int, Transform> Rtabmap::optimizedPoses() const {
  const std::map<int, Transform> current = impl_->graph.posesOfGroup(impl_->mapId);
  if (!current.empty() || impl_->lastNodeId != 0) return current;
  // A map without a node yet (a new session on an existing database, a new map): the map it
  // follows, until the first node of its own.
  const int newest = impl_->newestMapId();
  return newest < 0 ? current : impl_->graph.posesOfGroup(newest);
}

std::map<int, Transform> Rtabmap::landmarkPoses() const { return impl_->landmarkPoses; }

std::multimap<int, Link> Rtabmap::localLinks() const {
  if (!impl_->detector) return {};
  std::map<int, Transform> all;
  for (int id : workingMemory()) all.emplace(id, Transform::Identity());
  return impl_->ramLinks(all);
}

std::multimap<int, Link> Rtabmap::allLinks() const {
  std::multimap<int, Link> links;
  if (impl_->db) {
    impl_->db->flush();
    links = impl_->db->loadAllLinks(false);
  }
  // RAM holds links not saved yet (and links removed since): RAM wins for its nodes.
  const std::multimap<int, Link> ram = localLinks();
  std::set<int> inRam;
  for (int id : workingMemory()) inRam.insert(id);
  std::multimap<int, Link> out;
  for (const auto& [from, link] : links) {
    // A landmark is never in RAM: its links are the RAM node's.
    const bool ramHasIt = inRam.count(link.from()) && (link.to() < 0 || inRam.count(link.to()));
    if (!ramHasIt) out.emplace(from, link);
  }
  for (const auto& [from, link] : ram) out.emplace(from, link);
  return out;
}

std::vector<int> Rtabmap::workingMemory() const {
  std::vector<int> ids;
  if (!impl_->detector) return ids;
  const memory::Memory& m = impl_->detector->memory();
  for (const auto& [id, age] : m.wm()) {
    (void)age;
    ids.push_back(id);
  }
  ids.insert(ids.end(), m.stm().begin(), m.stm().end());
  return ids;
}

void Rtabmap::triggerNewMap() {
  if (!impl_->options.incremental) {
    RTABMAP_WARN("trigger new map ignored: localization mode does not modify the map");
    return;
  }
  impl_->newMapPending = true;
}

void Rtabmap::clockJumpedBack() {
  Impl& m = *impl_;
  m.lastStamp = 0.0;
  m.lastUpdateStamp = -1.0;
  m.odometryCache.clear();
  m.cacheMotion.setZero();
  m.carriedLandmarks.clear();  // in odometry that starts over
  if (m.options.incremental && m.lastNodeId != 0) {
    RTABMAP_WARN("the clock went back (a restarted bag or simulator): starting a new map");
    m.newMapPending = true;
  }
}

bool Rtabmap::setLabel(int nodeId, const std::string& label) {
  if (!impl_->detector) return false;
  const int owner = nodeOfLabelIn(impl_->labelCache, label);
  if (!label.empty() && owner != 0 && owner != nodeId) {
    RTABMAP_WARN("label \"" << label << "\" is already on node " << owner);
    return false;
  }
  if (!impl_->options.incremental) {
    RTABMAP_WARN("labels cannot be set in localization mode (the map is not modified)");
    return false;
  }
  if (!impl_->detector->memory().setLabel(nodeId, label)) return false;
  if (label.empty()) {
    impl_->labelCache.erase(nodeId);
  } else {
    impl_->labelCache[nodeId] = label;
  }
  return true;
}

std::map<int, std::string> Rtabmap::labels() const { return impl_->labelCache; }

int Rtabmap::nodeOfLabel(const std::string& label) const { return nodeOfLabelIn(impl_->labelCache, label); }

GridMap Rtabmap::gridMap() const { return impl_->grid ? impl_->grid->map() : GridMap(); }

}  // namespace rtabmap

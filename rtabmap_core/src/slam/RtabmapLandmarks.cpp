// Landmarks in the map (JFR 2019, 3.1): fiducial markers detected in a new node's images, or
// landmarks given with the input, tie every node that sees them through the landmark's own graph
// node. Seeing again a landmark an older node saw is a loop closure that needs no appearance
// match; seeing one that only another session saw merges the two maps.
#include "RtabmapImpl.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap {

void Rtabmap::Impl::detectMarkers(SensorData& data) {
  if (!markerDetector || !data.landmarks().empty() || data.imageRaw().empty()) return;
  StageTimer t(stats, "Timing/Marker_detection/ms");
  MarkerDetectionInfo info;
  data.setLandmarks(markerDetector->detect(data, &info));
  stats.addStatistic("Loop/Markers_detected/", static_cast<float>(data.landmarks().size()));
  if (info.idZero > 0) {
    RTABMAP_WARN("frame " << data.id() << ": marker id 0 ignored (a landmark's graph node is -id): use ids from 1");
  }
  if (info.withoutLength > 0) {
    RTABMAP_DEBUG("frame " << data.id() << ": " << info.withoutLength << " marker(s) without a length yet ("
                           << Parameters::kMarkerLength() << " 0: measured when seen facing the camera with depth)");
  }
}

void Rtabmap::Impl::carryLandmarks(const SensorData& skipped, const Transform& odom) {
  if (odom.isNull()) return;
  for (const auto& [id, l] : skipped.landmarks()) {
    Landmark inOdom = l;
    inOdom.pose = odom * l.pose;
    carriedLandmarks[id] = inOdom;  // the newest sighting
  }
}

void Rtabmap::Impl::takeCarriedLandmarks(SensorData& data, const Transform& odom) {
  if (carriedLandmarks.empty()) return;
  if (!odom.isNull()) {
    Landmarks all = data.landmarks();
    for (const auto& [id, l] : carriedLandmarks) {
      if (all.count(id)) continue;  // seen again by this frame
      Landmark here = l;
      here.pose = odom.inverse() * l.pose;
      all[id] = here;
    }
    data.setLandmarks(all);
  }
  carriedLandmarks.clear();
}

namespace {
// A landmark link says how the landmark is turned, not only where it is (Marker/VarianceAngular
// < 9999): one sighting from each of two maps then fixes how the maps sit, not only where.
bool orientationMeasured(const Link& l) { return l.infMatrix().diagonal().tail<3>().minCoeff() > 1e-3; }

// Node `seen.from()` to the node that made `other`, both sightings of one landmark: the
// transform through the landmark, weighted by both sightings' uncertainty (covariances summed).
Link throughLandmark(const Link& seen, const Link& other, Link::Type type) {
  const Eigen::Matrix<double, 6, 6> covariance = seen.infMatrix().inverse() + other.infMatrix().inverse();
  return Link(seen.from(), other.from(), type, seen.transform() * other.transform().inverse(),
              informationOf(covariance, false));
}
}  // namespace

std::vector<Link> Rtabmap::Impl::landmarkClosures(int newId) {
  std::vector<Link> closures;
  memory::Memory& memory = detector->memory();
  const Signature* fresh = memory.signature(newId);
  if (!fresh) return closures;
  std::vector<Link> seen;
  for (const auto& [to, link] : fresh->getLinks()) {
    if (link.type() == Link::kLandmark) seen.push_back(link);
  }
  if (seen.empty()) return closures;
  std::vector<int> ram(memory.stm().begin(), memory.stm().end());
  for (const auto& [id, age] : memory.wm()) {
    (void)age;
    ram.push_back(id);
  }
  const Transform pose = graph.pose(newId);
  for (const Link& link : seen) {
    const std::set<int> maps = graph.mapsMergedWith(mapId);  // (a merge below widens it)
    bool closes = false;
    const Link* elsewhere = nullptr;  // the nearest sighting from a map not merged with this one
    for (int id : ram) {
      const Signature* other = id == newId ? nullptr : memory.signature(id);
      const Link* view = other ? other->link(link.to(), Link::kLandmark) : nullptr;
      if (!view || graph.pose(id).isNull()) continue;
      if (maps.count(graph.mapOf(id))) {
        closes = true;
        break;
      }
      if (!elsewhere || view->transform().getNorm() < elsewhere->transform().getNorm()) elsewhere = view;
    }
    if (closes) {
      closures.push_back(link);
    } else if (elsewhere && orientationMeasured(link) && orientationMeasured(*elsewhere)) {
      // Another session saw it: a loop closure to the node that saw it nearest joins the maps,
      // and goes through the merge's vote, its undoing and the database like any other. It
      // replaces this node's own sighting (which it is made of: kept, it would count twice).
      const Link merge = throughLandmark(link, *elsewhere, Link::kGlobalClosure);
      memory.removeLink(newId, link.to(), Link::kLandmark);
      memory.addLink(merge);
      detector->linksChanged({merge.from(), merge.to()});
      graph.mergeMaps(graph.mapOf(merge.to()), mapId);
      closures.push_back(merge);
      RTABMAP_INFO("node " << newId << " saw landmark " << -link.to() << ", which map " << graph.mapOf(merge.to())
                           << " saw from node " << merge.to() << ": the maps are merged");
    } else if (!landmarkPoses.count(link.to()) && !pose.isNull()) {
      // First sight: where this node puts it, until an optimisation places it (and what tells
      // the next optimisation how far a closure through it moves the graph).
      landmarkPoses[link.to()] = pose * link.transform();
    }
  }
  return closures;
}

// In localization mode a marker the map saw places the robot at once: the temporary node's view
// of it and the view of the map node that saw it nearest make a link between the two nodes,
// weighted by both observations' uncertainty, which then goes through the odometry cache like
// a loop closure.
std::vector<Link> Rtabmap::Impl::landmarkLocalizations(int tempId) const {
  std::vector<Link> links;
  const memory::Memory& memory = detector->memory();
  const Signature* temp = memory.signature(tempId);
  if (!temp) return links;
  const std::map<int, Transform> poses = ramPosesOfGroup();
  for (const auto& [landmark, seen] : temp->getLinks()) {
    if (seen.type() != Link::kLandmark) continue;
    const Link* nearest = nullptr;
    for (const auto& [id, pose] : poses) {
      const Signature* s = id == tempId ? nullptr : memory.signature(id);
      const Link* view = s ? s->link(landmark, Link::kLandmark) : nullptr;
      if (view && (!nearest || view->transform().getNorm() < nearest->transform().getNorm())) nearest = view;
    }
    if (!nearest) continue;
    links.push_back(throughLandmark(seen, *nearest, Link::kLandmark));
  }
  return links;
}

}  // namespace rtabmap

// One update of RTAB-Map (JFR 2019, Figure 2; T-RO 2013, Algorithm 1): input checks, then the
// mapping update or the localization update, each a sequence of named stages timed into the
// statistics.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "ProximityBySpace.h"
#include "RtabmapImpl.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/geometry/ImageRectification.h"
#include "rtabmap_core/memory/ProcessMemory.h"

namespace rtabmap {
namespace {

bool isLostCovariance(const Covariance6& c) { return c.diagonal().maxCoeff() >= 9999.0; }

}  // namespace

bool Rtabmap::Impl::refuse(const std::string& why) {
  rejection = why;
  ++summary.refused;
  RTABMAP_WARN("update refused: " << why);
  return false;
}

bool Rtabmap::Impl::checkInput(const SensorData& data, const Transform& odom, const Covariance6& covariance) {
  if (options.metric) {
    if (odom.isNull()) return refuse("odometry pose is null (odometry lost or not started); waiting for a valid pose");
    if (odom.isInvalid()) return refuse("odometry pose is not finite: " + odom.prettyPrint());
    if (!covariance.allFinite()) return refuse("odometry covariance is not finite");
    if (isLostCovariance(covariance)) return refuse("odometry is lost (covariance 9999); waiting for it to recover");
  }
  if (!options.generateIds && options.incremental) {
    const int last = detector->memory().lastLocationId();
    if (data.id() <= 0) return refuse("the frame has no id (Mem/GenerateIds false needs one, > 0)");
    if (data.id() <= last) {
      return refuse("frame id " + std::to_string(data.id()) + " is not above the last node's " + std::to_string(last) +
                    " (Mem/GenerateIds false)");
    }
  }
  const double stamp = data.stamp();
  if (!std::isfinite(stamp)) return refuse("stamp is not finite");
  if (stamp > 0.0 && lastStamp > 0.0 && stamp < lastStamp) {
    // A bag restarted with its odometry: a new map. Otherwise an out-of-order frame.
    if (options.metric && odom.isIdentity(1e-6) && !lastOdom.isNull() && !lastOdom.isIdentity(1e-6)) return true;
    return refuse("stamp " + std::to_string(stamp) + " is older than the previous input's " + std::to_string(lastStamp) +
                  " (out of order, or time jumped back without an odometry reset)");
  }
  return true;
}

bool Rtabmap::Impl::rateLimited(double stamp) {
  if (options.detectionRate <= 0.0f || stamp <= 0.0 || lastUpdateStamp < 0.0) return false;
  // A small tolerance: a 1 Hz rate keeps the frame stamped 0.9999 s after the last update.
  return stamp - lastUpdateStamp < 1.0 / options.detectionRate - 1e-3;
}

bool Rtabmap::Impl::isStill(const Transform& odom) const {
  if (!options.metric || lastNodeOdom.isNull() || (options.linearUpdate <= 0.0f && options.angularUpdate <= 0.0f)) {
    return false;
  }
  const Transform motion = lastNodeOdom.inverse() * odom;
  return motion.getNorm() < options.linearUpdate && std::fabs(motion.getAngle()) < options.angularUpdate;
}

// RGBD/LinearSpeedUpdate, RGBD/AngularSpeedUpdate: the speed between the previous frame and this
// one, from their odometry and stamps. While it is above a limit the map is not updated: images
// blurred by motion make few words and a poor grid, and a fast turn smears a scan.
bool Rtabmap::Impl::tooFast(const Transform& odom, double stamp) const {
  if (options.linearSpeedUpdate <= 0.0f && options.angularSpeedUpdate <= 0.0f) return false;
  if (lastOdom.isNull() || stamp <= 0.0 || lastStamp <= 0.0 || stamp <= lastStamp) return false;
  const double dt = stamp - lastStamp;
  const Transform motion = lastOdom.inverse() * odom;
  return (options.linearSpeedUpdate > 0.0f && motion.getNorm() / dt > options.linearSpeedUpdate) ||
         (options.angularSpeedUpdate > 0.0f && std::fabs(motion.getAngle()) / dt > options.angularSpeedUpdate);
}

bool Rtabmap::Impl::process(const SensorData& data, const Transform& odom, const Covariance6& covariance) {
  if (!initialized) throw std::logic_error("Rtabmap::process: init() was not called");
  ++summary.updates;
  rejection.clear();
  goalReached = false;
  goalFailure.clear();
  if (!checkInput(data, odom, covariance)) return false;

  // Odometry reset (identity after motion, or a jump): a new map, as the original does.
  if (options.metric && options.incremental && !lastOdom.isNull() && lastNodeId != 0) {
    const bool backToIdentity = odom.isIdentity(1e-6) && !lastOdom.isIdentity(1e-6);
    const bool jumped = options.newMapOdomChangeDistance > 0.0f &&
                        (lastOdom.inverse() * odom).getNorm() > options.newMapOdomChangeDistance;
    if (backToIdentity || jumped) {
      RTABMAP_WARN("odometry was reset (" << (jumped ? "jump" : "identity pose") << "): starting a new map");
      newMapPending = true;
    }
  }
  if (newMapPending) motionCovariance.setZero();
  motionCovariance += covariance;
  if (!newMapPending && rateLimited(data.stamp())) {
    ++summary.skippedRate;
    addIntermediateNode(data, odom);
    carryLandmarks(data, odom);  // landmarks go to the next update's node all the same
    lastOdom = odom;
    if (data.stamp() > 0.0) lastStamp = data.stamp();
    return false;
  }
  if (!newMapPending && tooFast(odom, data.stamp())) {
    // The next frame is tried at once (the rate's clock did not restart).
    ++summary.skippedSpeed;
    carryLandmarks(data, odom);
    lastOdom = odom;
    lastStamp = data.stamp();
    return false;
  }
  if (newMapPending) startNewMap();
  applyStartPose(odom);
  lastOdom = odom;
  if (data.stamp() > 0.0) {
    lastStamp = data.stamp();
    lastUpdateStamp = data.stamp();
  }
  stats = Statistics();
  // Rtabmap/ImagesAlreadyRectified false: only the frames that make an update are rectified.
  std::optional<SensorData> rectified;
  if (!options.imagesAlreadyRectified && needsRectification(data)) {
    StageTimer t(stats, "Timing/Image_rectification/ms");
    try {
      rectified = rectifyImages(data);
    } catch (const Error& e) {
      return refuse(std::string("the images cannot be rectified (Rtabmap/ImagesAlreadyRectified false): ") + e.what());
    }
  }
  const SensorData& input = rectified ? *rectified : data;
  const bool used = options.incremental ? mappingUpdate(input, odom) : localizationUpdate(input, odom, covariance);
  if (used) {
    // After the statistics: Timing/Total/ms is the update's own time, as the time budget saw it.
    StageTimer t(stats, Statistics::kTimingMemory_release);
    memory::releaseFreedHeap();
  }
  if (!options.publishStats) stats.setData({});  // the structured results stay
  return used;
}

bool Rtabmap::Impl::addIntermediateNode(const SensorData& data, const Transform& odom) {
  if (!options.createIntermediateNodes || !options.incremental || !options.metric || lastNodeId == 0) return false;
  if (!lastChainOdom.isNull()) {
    const Transform motion = lastChainOdom.inverse() * odom;
    if (motion.getNorm() < options.linearUpdate && std::fabs(motion.getAngle()) < options.angularUpdate) return false;
  }
  memory::LoopClosureUpdate u;
  const memory::AddResult added = detector->addLocation(makeIntermediateLocation(data, odom, motionCovariance), u);
  forgetReducedNodes(added);
  graph.setPose(added.id, mapId, mapCorrection * odom);
  motionCovariance.setZero();  // the next node's neighbour link starts here
  lastChainOdom = odom;
  lastChainId = added.id;
  ++summary.intermediateNodes;
  return true;
}

// The first node of the current map taken back (Rtabmap/StartNewMapOnLoopClosure): the map is
// as if the frame had not come.
void Rtabmap::Impl::discardFirstNode(int id) {
  detector->memory().removeLastLocation();
  graph.erase(id);
  labelCache.erase(id);
  lastNodeId = 0;
  lastNodeOdom = Transform();
  lastChainOdom = Transform();
  lastChainId = 0;
  --summary.nodesAdded;
  ++summary.skippedMapStart;
}

void Rtabmap::Impl::forgetReducedNodes(const memory::AddResult& added) {
  const memory::Memory& memory = detector->memory();
  if (memory.options().reduceGraph) stats.addStatistic("Memory/Reduced_nodes/", static_cast<float>(added.reduced.size()));
  for (const auto& [id, into] : added.reduced) {
    const Transform reducedPose = graph.pose(id), intoPose = graph.pose(into);
    if (!reducedPose.isNull() && !intoPose.isNull()) stats.reducedTransforms[id] = intoPose.inverse() * reducedPose;
    graph.erase(id);
    if (grid) grid->removeLocalGrid(id);
    labelCache.erase(id);
    if (planner.isActive()) planner.renameNode(id, into);
    stats.reducedIds[id] = into;
    ++summary.reducedNodes;
    const auto held = std::remove_if(mergeLinks.begin(), mergeLinks.end(),
                                     [id = id](const Link& l) { return l.from() == id || l.to() == id; });
    if (held == mergeLinks.end()) continue;
    mergeLinks.erase(held, mergeLinks.end());
    // The composed links that now join the maps (recordMergeLinks keeps those) are among the
    // links of the nodes the reduced one was linked to.
    std::vector<Link> composed;
    const auto known = [&](const Link& l) {
      const auto same = [&l](const Link& m) {
        return (m.from() == l.from() && m.to() == l.to()) || (m.from() == l.to() && m.to() == l.from());
      };
      return std::any_of(mergeLinks.begin(), mergeLinks.end(), same) || std::any_of(composed.begin(), composed.end(), same);
    };
    for (int end : added.relinked) {
      const Signature* s = memory.signature(end);
      if (!s) continue;
      for (const auto& [to, l] : s->getLinks()) {
        if (l.type() == Link::kNeighborMerged && graph.contains(to) && !known(l)) composed.push_back(l);
      }
    }
    recordMergeLinks(composed);
  }
}

bool Rtabmap::Impl::mappingUpdate(const SensorData& data, const Transform& odom) {
  const auto start = std::chrono::steady_clock::now();
  memory::Memory& memory = detector->memory();
  memory::LoopClosureUpdate u;
  const size_t vocabularyAtStart = memory.vocabulary().size();
  const bool still = isStill(odom);

  // --- memory update: a new node, or rehearsal only when the robot did not move ---
  memory::AddResult added;
  {
    StageTimer t(stats, Statistics::kTimingMemory_update);
    added = detector->addLocation(makeLocation(data, odom, motionCovariance), u);
  }
  forgetReducedNodes(added);
  stats.addStatistic(Statistics::kMemoryRehearsal_merged, added.merged ? static_cast<float>(added.mergedWith) : 0.f);
  stats.addStatistic(Statistics::kMemorySimilarity, added.rehearsalSimilarity);
  stats.addStatistic(Statistics::kMemorySmall_movement, still ? 1.f : 0.f);
  if (added.id == 0) return refuse("frame " + std::to_string(data.id()) + " has too few visual words (Mem/BadSignaturesIgnored)");
  if (still) {
    // The robot stayed: the previous node was rehearsed (weight) if it looked the same; the
    // frame adds nothing to the map.
    ++summary.skippedStill;
    assembleDeferredGrid();
    if (!added.merged) {
      memory.removeLastLocation();
      return false;
    }
    finishStatistics(u, added.id, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    return true;
  }
  const int newId = added.id;
  const bool firstOfMap = lastNodeId == 0;
  if (firstOfMap && options.startNewMapOnGoodSignature && added.badSignature && !added.merged) {
    memory.removeLastLocation();
    ++summary.skippedMapStart;
    rejection = "map not started: the node has too few visual words (Rtabmap/StartNewMapOnGoodSignature)";
    return false;
  }
  const bool waitingForClosure = firstOfMap && options.metric && options.startNewMapOnLoopClosure && !added.merged &&
                                 graph.hasPoseOutside(mapId);
  if (options.metric && !added.merged) {
    graph.setPose(newId, mapId, mapCorrection * odom);
    motionCovariance.setZero();
    lastNodeOdom = odom;
    lastChainOdom = odom;
    lastChainId = newId;
    lastNodeId = newId;
    ++summary.nodesAdded;
    if (firstOfMap && options.mapLabelsAdded) {
      const std::string label = "map" + std::to_string(mapId);
      if (!labelCache.count(newId) && nodeOfLabelIn(labelCache, label) == 0 && memory.setLabel(newId, label)) {
        labelCache[newId] = label;
      }
    }
    if (options.neighborLinkRefining && !firstOfMap) refineNeighborLink(newId);
  }
  const std::vector<Link> timeLinks = options.metric && !added.merged ? proximityByTime(newId) : std::vector<Link>();
  const std::vector<Link> landmarkLinks = options.metric && !added.merged ? landmarkClosures(newId) : std::vector<Link>();

  // --- loop closure detection, verified by registration in metric SLAM, else by epipolar
  // geometry (VhEp/Enabled) ---
  detector->detect(newId, u, options.publishPdf, options.publishLikelihood);
  std::vector<Link> newLinks;
  if (u.highest.accepted) {
    std::optional<Link> link, refusedForJump;
    if (options.metric) {
      link = verifyLoopClosure(newId, u.highest.id, true, &refusedForJump);
    } else if (detector->verifyEpipolar(newId, u)) {
      link = Link(newId, u.highest.id, Link::kGlobalClosure, Transform::Identity());
    }
    if (link) {
      detector->acceptLoopClosure(*link);
      graph.mergeMaps(graph.mapOf(u.highest.id), mapId);
      newLinks.push_back(*link);
    } else {
      ++summary.rejectedLinks;
      stats.addStatistic(Statistics::kLoopRejected_hypothesis, 1.f);
      if (options.metric) newLinks = arbitrateMerge(newId, refusedForJump);
    }
  }

  // --- retrieval: around the hypothesis, and near the robot ---
  std::set<int> immune;
  {
    StageTimer t(stats, Statistics::kTimingReactivation);
    detector->retrieveNeighbors(u.highest.id, u, immune);
    if (options.metric) retrieveNearRobot(graph.pose(newId), u, immune);
  }
  const bool landmarkMerge = std::any_of(landmarkLinks.begin(), landmarkLinks.end(),
                                         [](const Link& l) { return l.type() == Link::kGlobalClosure; });
  if (waitingForClosure && newLinks.empty() && !landmarkMerge) {
    discardFirstNode(newId);
    rejection = "map not started: no loop closure with an earlier map yet (Rtabmap/StartNewMapOnLoopClosure)";
    return false;
  }

  // --- proximity detection by space ---
  if (options.metric && options.proximityBySpace && newLinks.empty()) {
    StageTimer t(stats, Statistics::kTimingProximity_by_space);
    ProximityResult p = detectProximityBySpace(memory, newId, ramPosesOfGroup(), options, *registration,
                                               options.covOffDiagIgnored);
    for (const Link& l : p.links) {
      memory.addLink(l);
      detector->linksChanged({l.from(), l.to()});
      graph.mergeMaps(graph.mapOf(l.to()), mapId);
      newLinks.push_back(l);
    }
    stats.addStatistic(Statistics::kProximitySpace_paths, static_cast<float>(p.paths));
    stats.addStatistic(Statistics::kProximitySpace_visual_paths_checked, static_cast<float>(p.visualChecked));
    stats.addStatistic(Statistics::kProximitySpace_scan_paths_checked, static_cast<float>(p.scanChecked));
    stats.addStatistic(Statistics::kProximitySpace_detections_added_visually, static_cast<float>(p.addedVisually));
    stats.addStatistic(Statistics::kProximitySpace_detections_added_icp_multi, static_cast<float>(p.addedByScans));
    for (const std::string& r : p.rejections) RTABMAP_DEBUG(r);
  }

  // --- optimisation of the local map, map -> odom ---
  if (options.metric) {
    if (!newLinks.empty() || !timeLinks.empty() || !landmarkLinks.empty() || !u.retrieved.empty()) {
      const bool onlyAClosure = newLinks.size() == 1 && newLinks.front().type() == Link::kGlobalClosure;
      newLinks.insert(newLinks.end(), timeLinks.begin(), timeLinks.end());
      newLinks.insert(newLinks.end(), landmarkLinks.begin(), landmarkLinks.end());
      std::vector<Link> kept = optimizeLocalMap(newId, newLinks);
      summary.rejectedLinks += static_cast<int>(newLinks.size() - kept.size());
      if (kept.empty() && onlyAClosure) {
        // The graph refused the closure (RGBD/OptimizeMaxError): without a jump limit, that is
        // how a true closure against a wrong merge ends, a vote against the merge as well.
        newLinks = arbitrateMerge(newId, newLinks.front());
        if (!newLinks.empty()) kept = optimizeLocalMap(newId, newLinks);
        summary.rejectedLinks += static_cast<int>(newLinks.size() - kept.size());
      }
      recordMergeLinks(kept);
      int timeKept = 0;
      for (const Link& l : kept) {
        if (l.type() == Link::kGlobalClosure) {
          ++summary.loopClosures;
          stats.loopClosureId = l.to();
          stats.loopClosureTransform = l.transform();
        } else if (l.type() == Link::kLocalTimeClosure) {
          ++summary.timeLinks;
          ++timeKept;
        } else if (l.type() == Link::kLandmark) {
          ++summary.landmarkClosures;
          stats.landmarkId = l.to();
        } else {
          ++summary.proximityLinks;
          stats.proximityDetectionId = l.to();
        }
      }
      if (options.proximityByTime) stats.addStatistic(Statistics::kProximityTime_detections, static_cast<float>(timeKept));
    }
    const Transform pose = graph.pose(newId);
    if (!pose.isNull()) {
      mapCorrection = pose * odom.inverse();
      currentPose = pose;
    }
    if (grid) {
      StageTimer t(stats, Statistics::kTimingMap_assembling);
      const Signature* s = memory.signature(newId);
      if (s && !s->sensorData().localGrid().isEmpty()) grid->addLocalGrid(newId, s->sensorData().localGrid());
      const GridUpdateSummary g = grid->update(graph.posesOfGroup(mapId));
      // Cells of nodes out of the Working Memory read back for this re-assembly (issue 10).
      stats.addStatistic("Memory/Grid_nodes_read_back/", static_cast<float>(g.nodesLoaded));
      stats.addStatistic("Memory/Grid_nodes_in_layers/", static_cast<float>(g.nodesInLayers));
      stats.addStatistic("Memory/Grid_nodes_not_read_back/", static_cast<float>(g.nodesNotLoaded));
      stats.addStatistic("Timing/Grid_read_back/ms", static_cast<float>(g.loadMs));
      // What the assembly did, to tell a re-assembly's cost from its cause (moved nodes).
      stats.addStatistic("Memory/Grid_path/", static_cast<float>(g.path));
      stats.addStatistic("Memory/Grid_updates_deferred/", static_cast<float>(g.updatesDeferred));
      stats.addStatistic("Memory/Grid_nodes_moved/", static_cast<float>(g.nodesMoved));
      stats.addStatistic("Memory/Grid_nodes_replayed/", static_cast<float>(g.nodesReplayed));
      stats.addStatistic("Memory/Grid_cell_updates/", static_cast<float>(g.cellUpdates));
    }
  } else if (u.highest.accepted && !newLinks.empty()) {
    ++summary.loopClosures;
    stats.loopClosureId = newLinks.front().to();
  }

  // --- path following: upcoming path nodes come back from LTM and stay ---
  if (options.metric) followPlan(newId, u, immune);

  // --- memory management: transfer when over the time or size budget ---
  {
    StageTimer t(stats, Statistics::kTimingMemory_cleanup);
    const std::set<int> local = localImmunity(graph.pose(newId));
    immune.insert(local.begin(), local.end());
    stats.addStatistic(Statistics::kMemoryImmunized_locally, static_cast<float>(local.size()));
    const double elapsed = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    detector->manageMemory(immune, elapsed, vocabularyAtStart, u);
    evictTransferredGrids(u);
  }
  summary.transferred += static_cast<int>(u.transferred.size());
  summary.retrieved += static_cast<int>(u.retrieved.size());
  const double total = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  finishStatistics(u, newId, total);
  addGroundTruthStatistics(newId);  // an evaluation, outside the update's time
  return true;
}

bool Rtabmap::Impl::localizationUpdate(const SensorData& data, const Transform& odom, const Covariance6& covariance) {
  const auto start = std::chrono::steady_clock::now();
  memory::Memory& memory = detector->memory();
  // (Where the robot is assumed before its first localisation: applyStartPose().)
  if (localized && isStill(odom)) {
    ++summary.skippedStill;
    return false;
  }
  memory::LoopClosureUpdate u;
  const size_t vocabularyAtStart = memory.vocabulary().size();
  memory::AddResult added;
  {
    StageTimer t(stats, Statistics::kTimingMemory_update);
    added = detector->addLocation(makeLocation(data, odom, covariance), u);
  }
  cacheMotion += motionCovariance;
  motionCovariance.setZero();
  if (added.id == 0) return refuse("frame " + std::to_string(data.id()) + " has too few visual words");
  const int tempId = added.id;
  const Transform estimate = mapCorrection * odom;
  odometryCache.addFrame(odom, informationOf(cacheMotion, options.covOffDiagIgnored));
  cacheMotion.setZero();
  graph.setPose(tempId, mapId, estimate);

  // Localisations: a verified loop closure, else proximity links to the map near the estimate.
  std::vector<Link> found;
  detector->detect(tempId, u, options.publishPdf, options.publishLikelihood);
  if (u.highest.accepted) {
    if (std::optional<Link> l = verifyLoopClosure(tempId, u.highest.id, localized)) found.push_back(*l);
  }
  std::set<int> immune;
  detector->retrieveNeighbors(u.highest.id, u, immune);
  retrieveNearRobot(estimate, u, immune);
  if (found.empty()) found = landmarkLocalizations(tempId);
  if (found.empty() && options.proximityBySpace) {
    StageTimer t(stats, Statistics::kTimingProximity_by_space);
    // The temporary node is linked to nothing: a graph depth from it would leave no candidate.
    // The local radius around the estimate (last localisation or the user's initial pose,
    // moved by odometry) bounds the search instead.
    const bool global = options.proximityGlobalScanMap && registration->usesScans();
    if (global && !globalScanMap) buildGlobalScanMap(tempId);
    ProximityResult p;
    if (global && !globalScanMap->empty()) {
      p = localizeOnGlobalScanMap(memory, tempId, estimate, *globalScanMap, options, *registration,
                                  options.covOffDiagIgnored);
    } else {
      RtabmapOptions unlinked = options;
      unlinked.proximityMaxGraphDepth = 0;
      p = detectProximityBySpace(memory, tempId, ramPosesOfGroup(), unlinked, *registration,
                                 options.covOffDiagIgnored);
    }
    for (const std::string& why : p.rejections) RTABMAP_DEBUG(why);
    stats.addStatistic(Statistics::kProximitySpace_paths, static_cast<float>(p.paths));
    stats.addStatistic(Statistics::kProximitySpace_visual_paths_checked, static_cast<float>(p.visualChecked));
    stats.addStatistic(Statistics::kProximitySpace_scan_paths_checked, static_cast<float>(p.scanChecked));
    stats.addStatistic(Statistics::kProximitySpace_detections_added_visually, static_cast<float>(p.addedVisually));
    stats.addStatistic(Statistics::kProximitySpace_detections_added_icp_multi, static_cast<float>(p.addedByScans));
    found = p.links;
  }
  lastNodeOdom = odom;
  bool used = false;
  for (const Link& l : found) {
    const Transform there = graph.pose(l.to());
    if (there.isNull()) continue;
    const Transform pose = there * l.transform().inverse();
    if (localized && options.maxLoopClosureDistance > 0.0f && pose.getDistance(estimate) > options.maxLoopClosureDistance) {
      RTABMAP_INFO("localization on node " << l.to() << " rejected: it moves the robot by " << pose.getDistance(estimate)
                                           << " m (" << Parameters::kRGBDMaxLoopClosureDistance() << ")");
      continue;
    }
    const OdometryCacheVerdict verdict = odometryCache.verify({l, there});
    if (verdict.proximityDropped > 0) {
      RTABMAP_INFO("loop closure on node " << l.to() << " disagrees with " << verdict.proximityDropped
                                           << " cached proximity localization(s): they are dropped");
    }
    if (!verdict.accepted || !verdict.confirmed) {
      RTABMAP_INFO("localization on node " << l.to() << (verdict.accepted ? " kept: " : " rejected: ") << verdict.why);
      continue;
    }
    mapCorrection = verdict.pose * odom.inverse();
    localized = true;
    used = true;
    ++summary.localizations;
    if (l.type() == Link::kGlobalClosure) {
      stats.loopClosureId = l.to();
    } else if (l.type() == Link::kLandmark) {
      // The marker both nodes saw.
      const Signature* temp = memory.signature(tempId);
      const Signature* there = memory.signature(l.to());
      for (const auto& [to, seen] : temp->getLinks()) {
        if (seen.type() == Link::kLandmark && to < 0 && there && there->hasLink(to, Link::kLandmark)) {
          stats.landmarkId = to;
          break;
        }
      }
    } else {
      stats.proximityDetectionId = l.to();
    }
    break;
  }
  currentPose = mapCorrection * odom;
  followPlan(0, u, immune);
  // The temporary node is forgotten: the map is not modified.
  memory.removeLastLocation();
  graph.erase(tempId);
  detector->manageMemory(immune, 0.0, vocabularyAtStart, u);
  evictTransferredGrids(u);
  summary.transferred += static_cast<int>(u.transferred.size());
  summary.retrieved += static_cast<int>(u.retrieved.size());
  const double total = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  finishStatistics(u, 0, total);
  return used;
}

void Rtabmap::Impl::finishStatistics(const memory::LoopClosureUpdate& u, int nodeId, double totalMs) {
  const memory::Memory& memory = detector->memory();
  stats.refImageId = nodeId;
  stats.refImageMapId = nodeId ? graph.mapOf(nodeId) : -1;
  stats.stamp = lastStamp;
  stats.mapCorrection = mapCorrection;
  stats.posterior = u.posterior;
  stats.likelihood = u.likelihood;
  if (options.saveWmState) {
    stats.wmState.assign(memory.stm().begin(), memory.stm().end());
    for (const auto& [id, age] : memory.wm()) {
      (void)age;
      stats.wmState.push_back(id);
    }
    std::sort(stats.wmState.begin(), stats.wmState.end());
  }
  stats.addStatistic(Statistics::kLoopHighest_hypothesis_id, static_cast<float>(u.highest.id));
  stats.addStatistic(Statistics::kLoopHighest_hypothesis_value, u.highest.value);
  stats.addStatistic(Statistics::kLoopAccepted_hypothesis_id, static_cast<float>(stats.loopClosureId));
  stats.addStatistic(Statistics::kLoopMap_id, static_cast<float>(mapId));
  stats.addStatistic(Statistics::kLoopLast_id, static_cast<float>(memory.lastLocationId()));
  stats.addStatistic(Statistics::kLoopVisual_words, static_cast<float>(u.words));
  stats.addStatistic(Statistics::kProximitySpace_last_detection_id, static_cast<float>(stats.proximityDetectionId));
  stats.addStatistic(Statistics::kLoopLandmark_detected, static_cast<float>(stats.landmarkId));
  stats.addStatistic(Statistics::kTimingLikelihood_computation, static_cast<float>(u.likelihoodMs));
  stats.addStatistic(Statistics::kTimingPosterior_computation, static_cast<float>(u.posteriorMs));
  stats.addStatistic(Statistics::kTimingHypotheses_creation, static_cast<float>(u.hypothesisMs));
  // Locations: the intermediate nodes in RAM are counted on their own.
  const memory::MemorySummary sizes = memory.summary();
  stats.addStatistic(Statistics::kMemoryWorking_memory_size, static_cast<float>(sizes.wmSize));
  stats.addStatistic(Statistics::kMemoryShort_time_memory_size, static_cast<float>(sizes.stmSize));
  if (options.createIntermediateNodes) {
    stats.addStatistic("Memory/Intermediate_nodes_in_RAM/", static_cast<float>(sizes.intermediatesInRam));
  }
  stats.addStatistic(Statistics::kMemorySignatures_retrieved, static_cast<float>(u.retrieved.size()));
  stats.addStatistic(Statistics::kMemorySignatures_removed, static_cast<float>(u.transferred.size()));
  stats.addStatistic(Statistics::kKeypointDictionary_size, static_cast<float>(memory.vocabulary().size()));
  // Where the RAM goes (the soak's memory goal): live heap, what malloc keeps free, SQLite's
  // caches, and the global grid's per-node cells (the one cache of the whole map, LTM included).
  constexpr float kMb = 1.0f / (1024.0f * 1024.0f);
  const rtabmap::memory::HeapStats heap = rtabmap::memory::heapStats();
  stats.addStatistic(Statistics::kMemoryRAM_usage, static_cast<float>(heap.inUse) * kMb);
  stats.addStatistic("Memory/Heap_free/MB", static_cast<float>(heap.free) * kMb);
  stats.addStatistic(Statistics::kMemoryDatabase_memory_used, static_cast<float>(rtabmap::memory::sqliteInUse()) * kMb);
  const size_t locations = memory.locationsMemoryUsed(), vocabulary = memory.vocabulary().memoryUsed();
  const size_t gridBytes = grid ? grid->memoryUsed() : 0;
  stats.addStatistic("Memory/Locations_memory_used/MB", static_cast<float>(locations) * kMb);
  stats.addStatistic("Memory/Vocabulary_memory_used/MB", static_cast<float>(vocabulary) * kMb);
  stats.addStatistic("Memory/Vocabulary_index_points/", static_cast<float>(memory.vocabulary().indexPoints()));
  if (grid) {
    stats.addStatistic("Memory/Grid_memory_used/MB", static_cast<float>(gridBytes) * kMb);
    stats.addStatistic("Memory/Grid_nodes_resident/", static_cast<float>(grid->residentNodes()));
  }
  // The map's own structures, as the original's estimate: locations, vocabulary, grid, SQLite.
  stats.addStatistic(Statistics::kMemoryRAM_estimated,
                     static_cast<float>(locations + vocabulary + gridBytes + rtabmap::memory::sqliteInUse()) * kMb);
  stats.addStatistic(Statistics::kTimingTotal, static_cast<float>(totalMs));
  if (db && options.incremental) {
    // What is safe on disk: every node up to this one survives a crash (the writer commits in
    // order); a failed writer (disk full...) keeps new nodes in RAM only until it recovers.
    const db::WriterStatus w = db->writerStatus();
    stats.addStatistic(Statistics::kMemoryDurable_node_id, static_cast<float>(w.lastDurableNodeId));
    stats.addStatistic(Statistics::kMemoryDatabase_write_failed, w.failed ? 1.0f : 0.0f);
  }
  const Transform c = mapCorrection;
  stats.addStatistic(Statistics::kLoopOdom_correction_norm, static_cast<float>(c.getNorm()));
  stats.addStatistic(Statistics::kLoopOdom_correction_angle, static_cast<float>(c.getAngle() * 180.0 / M_PI));
  summary.maxWmSize = std::max(summary.maxWmSize, memory.wmLocations());
}

}  // namespace rtabmap

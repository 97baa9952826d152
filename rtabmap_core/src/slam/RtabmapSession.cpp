// Rtabmap sessions: opening a map (new or existing: multi-session, IROS 2014), the Working
// Memory it starts with, new maps, closing.
#include <algorithm>
#include <chrono>
#include <filesystem>

#include "RtabmapImpl.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap {

void Rtabmap::Impl::open(const ParametersMap& p, const std::string& databasePath) {
  Parameters::validate(p);
  parameters = p;
  options = RtabmapOptions::fromParameters(p);
  detectorOptions = memory::LoopClosureDetectorOptions::fromParameters(p);
  optimizer = OptimizerOptions::fromParameters(p);
  {
    MergeArbiterOptions merge;
    merge.planar = optimizer.force3DoF;
    mergeArbiter = MergeArbiter(merge);
  }
  planner = PathPlanner(PlannerOptions::fromParameters(p));
  scanFilter = ScanFilterOptions::fromParameters(p);
  {
    OdometryCacheOptions cache;
    cache.maxSize = options.maxOdomCacheSize;
    cache.maxErrorRatio = options.optimizeMaxError;
    cache.optimizer = optimizer;
    odometryCache = OdometryCache(cache);
  }
  if (options.metric) registration = std::make_unique<LinkRegistration>(p);
  if (!options.binDataKept && registration && registration->visualNeedsImages()) {
    RTABMAP_WARN(Parameters::kMemBinDataKept() << " is false but the visual registration of loop closures reads the "
                                               << "nodes' images (" << Parameters::kVisCorType() << " 1, "
                                               << Parameters::kVisEstimationType() << " 0 or "
                                               << Parameters::kVisForwardEstOnly()
                                               << " false): every loop closure's transform will fail");
  }
  if (options.createIntermediateNodes && detectorOptions.memory.reduceGraph) {
    RTABMAP_WARN(Parameters::kMemReduceGraph() << " does not merge nodes next to intermediate nodes ("
                                               << Parameters::kRtabmapCreateIntermediateNodes()
                                               << " keeps the whole trajectory): with both, the graph is not reduced");
  }
  if (options.createOccupancyGrid) {
    gridOptions = LocalGridOptions::fromParameters(p);
    grid = std::make_unique<OccupancyGrid>(GlobalGridOptions::fromParameters(p));
  }
  if (Parameters::getBool(p, Parameters::kRGBDMarkerDetection())) {
    markerDetector = std::make_unique<MarkerDetector>(MarkerDetectorOptions::fromParameters(p));
  }
  if (Parameters::getInt(p, Parameters::kKpMaxFeatures()) >= 0) {
    wordDetector = FeatureDetector::create(p, FeatureGroup::kKp);
    odomFeaturesCompatible =
        Parameters::getInt(p, Parameters::kKpDetectorStrategy()) == Parameters::getInt(p, Parameters::kVisFeatureType());
  }

  if (!databasePath.empty()) {
    db::DatabaseOptions dbOptions = db::DatabaseOptions::fromParameters(p);
    // Localization never modifies the map: not even a session row.
    dbOptions.readOnly = !options.incremental;
    if (!options.incremental && !std::filesystem::exists(databasePath)) {
      throw DatabaseError("localization mode (" + Parameters::kMemIncrementalMemory() + " false) needs an existing map: " +
                          databasePath + " does not exist");
    }
    dbOptions.imageFormat = options.imageFormat;
    db = std::make_unique<db::Database>(databasePath, dbOptions);
  }
  detector = std::make_unique<memory::LoopClosureDetector>(detectorOptions, db.get());
  if (grid && db) {
    // The global grid keeps the cells of Working Memory nodes only (issue 10): those of a node
    // leaving it are read back, when a re-assembly replays the node, from the Working Memory
    // (a retrieved node) or else from the local grid stored with the node.
    grid->setGridLoader([this](const std::vector<int>& ids) {
      std::map<int, LocalGrid> grids;
      std::vector<int> stored;
      const memory::Memory& memory = detector->memory();
      for (int id : ids) {
        const Signature* s = memory.signature(id);
        if (s && !s->sensorData().localGrid().isEmpty()) {
          grids.emplace(id, s->sensorData().localGrid());
        } else {
          stored.push_back(id);
        }
      }
      if (!stored.empty()) {
        db::LoadOptions gridOnly = db::LoadOptions::nodeOnly();
        gridOnly.grid = true;
        for (Signature& s : db->loadNodes(stored, gridOnly)) {
          if (!s.sensorData().localGrid().isEmpty()) grids.emplace(s.id(), s.sensorData().localGrid());
        }
      }
      return grids;
    });
  }
  mapId = 0;
  if (db) mapId = options.incremental ? db->sessionMapId() : std::max(0, db->lastMapId());
  if (db && db->lastNodeId() > 0) loadExistingMap();
  summary.mapsStarted = options.incremental ? 1 : 0;
  initialized = true;
}

// Every node of the database is known to the session graph with its pose, optimised once per
// connected component (the oldest node of each fixed), so earlier sessions are in their own
// referential and the maps merged by links share the oldest one's.
void Rtabmap::Impl::loadExistingMap() {
  const std::map<int, Signature> headers = db->loadAllNodeHeaders();
  const std::multimap<int, Link> links = db->loadAllLinks(false);
  std::map<int, Transform> odomPoses;
  for (const auto& [id, s] : headers) {
    graph.setPose(id, s.mapId(), Transform());
    odomPoses.emplace(id, s.getPose().isNull() ? Transform::Identity() : s.getPose());
    if (!s.label().empty()) labelCache[id] = s.label();
  }
  for (const auto& [from, link] : links) {
    const int a = graph.mapOf(link.from()), b = graph.mapOf(link.to());
    if (a >= 0 && b >= 0 && a != b) graph.mergeMaps(a, b);
  }
  std::vector<std::string> failures;
  graph.updatePoses(optimizeEachComponent(optimizer, odomPoses, links, &failures));
  for (const std::string& f : failures) RTABMAP_WARN(f << " (at start)");
  // Localization starts where the last session ended, unless RGBD/StartAtOrigin.
  initialLocalizationPose = graph.pose(db->lastNodeId());

  std::vector<int> allIds;
  for (const auto& [id, s] : headers) allIds.push_back(id);
  loadWorkingMemory(allIds);
  if (grid) loadLocalGrids(allIds);
  RTABMAP_INFO("loaded map " << db->path() << ": " << headers.size() << " nodes, " << links.size() << " links, "
                             << detector->memory().wm().size() << " in Working Memory; new map id " << mapId);
}

// Mem/InitWMWithAllNodes: every node; otherwise the Working Memory the last session closed
// with (all nodes when it did not close cleanly and left none).
void Rtabmap::Impl::loadWorkingMemory(const std::vector<int>& allIds) {
  std::vector<int> ids;
  if (!options.initWMWithAllNodes) {
    const std::optional<db::StoredStatistics> last = db->loadStatistics(db->lastNodeId());
    if (last) ids = last->wmState;
  }
  if (ids.empty()) ids = allIds;
  detector->memory().retrieveIds(ids);
}

void Rtabmap::Impl::loadLocalGrids(const std::vector<int>& ids) {
  db::LoadOptions gridOnly = db::LoadOptions::nodeOnly();
  gridOnly.grid = true;
  constexpr size_t kBatch = 256;
  for (size_t i = 0; i < ids.size(); i += kBatch) {
    const std::vector<int> batch(ids.begin() + i, ids.begin() + std::min(ids.size(), i + kBatch));
    for (const Signature& s : db->loadNodes(batch, gridOnly)) {
      if (s.sensorData().localGrid().isEmpty()) continue;
      grid->addLocalGrid(s.id(), s.sensorData().localGrid());
      // Out of the Working Memory: only what the map needs to know about it stays in RAM.
      if (!detector->memory().signature(s.id())) grid->evictLocalGrid(s.id());
    }
  }
}

void Rtabmap::Impl::buildGlobalScanMap(int excludedId) {
  const auto start = std::chrono::steady_clock::now();
  memory::Memory& memory = detector->memory();
  std::map<int, Transform> poses = graph.posesOfGroup(mapId);
  poses.erase(excludedId);
  globalScanMap = std::make_unique<GlobalScanMap>(registration->icpVoxelSize());
  globalScanMap->setNodes(poses);
  std::vector<std::pair<LaserScan, Transform>> parts;
  std::vector<int> inDatabase;
  for (const auto& [id, pose] : poses) {
    if (const Signature* s = memory.signature(id)) {
      // Uncompressed in a copy: scanOf() keeps the raw points in the node it is given, and a
      // Working Memory of 3D lidar nodes would then hold all of them.
      Signature copy(*s);
      parts.emplace_back(scanOf(copy), pose);
    } else {
      inDatabase.push_back(id);
    }
  }
  globalScanMap->add(parts);
  db::LoadOptions scanOnly = db::LoadOptions::nodeOnly();
  scanOnly.scan = true;
  constexpr size_t kBatch = 256;  // the raw points of one batch at a time (3D lidars)
  for (size_t i = 0; db && i < inDatabase.size(); i += kBatch) {
    const std::vector<int> batch(inDatabase.begin() + i, inDatabase.begin() + std::min(inDatabase.size(), i + kBatch));
    parts.clear();
    for (Signature& s : db->loadNodes(batch, scanOnly)) parts.emplace_back(scanOf(s), poses.at(s.id()));
    globalScanMap->add(parts);
  }
  globalScanMap->finish();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  RTABMAP_INFO("global scan map (" << Parameters::kRGBDProximityGlobalScanMap() << "): " << globalScanMap->points()
                                   << " points from " << poses.size() << " nodes (" << inDatabase.size()
                                   << " read from the database) in " << ms << " ms"
                                   << (globalScanMap->skippedParts() ? ", scans of another format skipped: " +
                                                                           std::to_string(globalScanMap->skippedParts())
                                                                     : std::string()));
}

void Rtabmap::Impl::startNewMap() {
  newMapPending = false;
  if (lastNodeId == 0 && summary.nodesAdded == 0) return;  // nothing in the current map yet
  const int previous = mapId;
  mapId = std::max(mapId, std::max(graph.mapOf(lastNodeId), db ? db->lastMapId() : 0)) + 1;
  mapCorrection = Transform::Identity();
  lastNodeOdom = Transform();
  lastChainOdom = Transform();
  lastChainId = 0;
  lastNodeId = 0;
  mergeLinks.clear();
  mergeArbiter.reset();
  landmarkPoses.clear();  // placed in the previous map's referential
  carriedLandmarks.clear();  // in the previous odometry's frame
  ++summary.mapsStarted;
  RTABMAP_INFO("new map " << mapId << " (previous " << previous << ")");
}

void Rtabmap::Impl::close() {
  if (!initialized) return;
  initialized = false;
  if (db && options.incremental) {
    memory::Memory& memory = detector->memory();
    memory.saveAll();
    // The Working Memory this session ends with is where the next one starts.
    // Kept with the newest node in RAM: the database's last node once everything is saved,
    // where the next session looks for it.
    db::StoredStatistics last;
    for (int id : memory.stm()) last.wmState.push_back(id);
    for (const auto& [id, age] : memory.wm()) {
      (void)age;
      last.wmState.push_back(id);
    }
    last.data = stats.data();
    if (!last.wmState.empty()) {
      last.nodeId = *std::max_element(last.wmState.begin(), last.wmState.end());
      db->saveStatistics(last);
    }
  }
  detector.reset();
  if (db) {
    std::unique_ptr<db::Database> closing = std::move(db);
    closing->close();
  }
}

}  // namespace rtabmap

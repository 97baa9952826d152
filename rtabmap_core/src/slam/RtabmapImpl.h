#pragma once
// Internals of Rtabmap (private to the slam area): the state one session keeps between
// updates, and the stages of an update, each a small function (RtabmapUpdate.cpp,
// RtabmapGraph.cpp, RtabmapNode.cpp, RtabmapSession.cpp).
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "GlobalScanMap.h"
#include "LinkRegistration.h"
#include "MergeArbiter.h"
#include "OdometryCache.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/features/MarkerDetector.h"
#include "rtabmap_core/maps/LocalGridOptions.h"
#include "rtabmap_core/maps/OccupancyGrid.h"
#include "rtabmap_core/memory/LoopClosureDetector.h"
#include "rtabmap_core/optimizer/Optimizer.h"
#include "rtabmap_core/registration/ScanFilter.h"
#include "rtabmap_core/slam/PathPlanner.h"
#include "rtabmap_core/slam/Rtabmap.h"
#include "rtabmap_core/slam/RtabmapOptions.h"
#include "rtabmap_core/slam/SessionGraph.h"

namespace rtabmap {

using Covariance6 = Eigen::Matrix<double, 6, 6>;

// The node holding `label`, 0 if none.
inline int nodeOfLabelIn(const std::map<int, std::string>& labels, const std::string& label) {
  for (const auto& [id, l] : labels) {
    if (l == label) return id;
  }
  return 0;
}

// Times one stage into a statistic (ms).
class StageTimer {
 public:
  StageTimer(Statistics& stats, const char* key) : stats_(stats), key_(key), start_(std::chrono::steady_clock::now()) {}
  ~StageTimer() { stats_.addStatistic(key_, static_cast<float>(ms())); }
  double ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  Statistics& stats_;
  const char* key_;
  std::chrono::steady_clock::time_point start_;
};

struct Rtabmap::Impl {
  // --- configuration ---
  ParametersMap parameters;
  RtabmapOptions options;
  memory::LoopClosureDetectorOptions detectorOptions;
  OptimizerOptions optimizer;
  std::optional<LocalGridOptions> gridOptions;
  ScanFilterOptions scanFilter;  // Mem/LaserScan*: the scan a new node keeps

  // --- components ---
  std::unique_ptr<db::Database> db;
  std::unique_ptr<memory::LoopClosureDetector> detector;
  std::unique_ptr<FeatureDetector> wordDetector;  // Kp/ features when odometry's cannot be reused
  bool odomFeaturesCompatible = false;           // Kp/DetectorStrategy == Vis/FeatureType
  std::unique_ptr<MarkerDetector> markerDetector;  // RGBD/MarkerDetection
  std::unique_ptr<LinkRegistration> registration;
  std::unique_ptr<OccupancyGrid> grid;
  SessionGraph graph;
  PathPlanner planner;
  bool goalReached = false;
  std::string goalFailure;

  // --- session state ---
  bool initialized = false;
  int mapId = 0;
  bool newMapPending = false;
  Transform mapCorrection = Transform::Identity();
  Transform lastOdom;          // odometry pose of the last accepted input
  Transform lastNodeOdom;      // odometry pose of the last node of the current map
  // ... of the last node or intermediate node (Rtabmap/CreateIntermediateNodes): a new
  // intermediate node needs motion since it.
  Transform lastChainOdom;
  int lastChainId = 0;
  int lastNodeId = 0;          // last node of the current map
  double lastStamp = 0.0;      // stamp of the last accepted input
  double lastUpdateStamp = -1.0;  // stamp of the last update that passed the rate limit
  Transform currentPose;       // robot in the map at the last update
  // Covariance of the odometry motion since the last node: the sum of the frames' incremental
  // covariances (frames skipped by the rate or while still included), the neighbour link's.
  Covariance6 motionCovariance = Covariance6::Zero();
  // Localization mode
  bool localized = false;
  // The recent localization frames and their links: a new localization must fit them
  // (RGBD/MaxOdomCacheSize), and the motion since the last cached frame.
  OdometryCache odometryCache;
  Covariance6 cacheMotion = Covariance6::Zero();
  Transform initialLocalizationPose;  // last pose of the saved map (RGBD/StartAtOrigin false)
  Transform initialPose;              // given by the user, applied at the next update (null: none)
  // RGBD/ProximityGlobalScanMap: built at the first localization update that needs it (the map
  // does not change in localization mode).
  std::unique_ptr<GlobalScanMap> globalScanMap;
  std::map<int, std::string> labelCache;
  // Multi-session: the links this process added between the current map and earlier ones, and
  // the vote on whether they merged it at the right place.
  std::vector<Link> mergeLinks;
  MergeArbiter mergeArbiter;
  // Landmarks (RGBD/MarkerDetection or given with the input): where the last optimisation of a
  // local map that saw them put them, by graph id (< 0), in the current referential.
  std::map<int, Transform> landmarkPoses;
  // Landmarks of input frames skipped by the rate (Rtabmap/DetectionRate) or the speed limit,
  // by id, their poses in the odometry frame: the next frame that makes an update takes them
  // (a detector's output is rarer than frames and must not fall between updates).
  Landmarks carriedLandmarks;

  // --- outputs ---
  Statistics stats;
  SlamSummary summary;
  std::string rejection;

  // RtabmapSession.cpp
  void open(const ParametersMap& parameters, const std::string& databasePath);
  void loadExistingMap();
  void loadWorkingMemory(const std::vector<int>& allIds);
  void loadLocalGrids(const std::vector<int>& ids);
  // RGBD/ProximityGlobalScanMap: the scans of every node of the current referential but
  // `excludedId` (the temporary localization node), from RAM or the database.
  void buildGlobalScanMap(int excludedId);
  void close();
  void startNewMap();

  // RtabmapUpdate.cpp
  bool process(const SensorData& data, const Transform& odom, const Covariance6& covariance);
  bool refuse(const std::string& why);
  bool checkInput(const SensorData& data, const Transform& odom, const Covariance6& covariance);
  bool rateLimited(double stamp);
  bool isStill(const Transform& odom) const;
  bool tooFast(const Transform& odom, double stamp) const;
  bool mappingUpdate(const SensorData& data, const Transform& odom);
  // Rtabmap/CreateIntermediateNodes: a frame the rate skipped, kept as an intermediate node if
  // the map has started and the robot moved since the last node (true if added).
  bool addIntermediateNode(const SensorData& data, const Transform& odom);
  // Rtabmap/StartNewMapOnLoopClosure: the first node of the current map taken back.
  void discardFirstNode(int id);
  // Mem/ReduceGraph: nodes merged into older ones as they left STM leave the graph, the global
  // grid and the labels; a plan through one goes through the node it merged into, and a merge
  // link one held is handed to the composed links that now join the maps.
  void forgetReducedNodes(const memory::AddResult& added);
  bool localizationUpdate(const SensorData& data, const Transform& odom, const Covariance6& covariance);
  void finishStatistics(const memory::LoopClosureUpdate& u, int nodeId, double totalMs);
  // RtabmapGraph.cpp: Rtabmap/ComputeRMSE (GroundTruthError.h), when the node has ground truth.
  void addGroundTruthStatistics(int nodeId);
  // The robot stands still, no update comes: graph changes the global grid deferred
  // (GridGlobal/ReassemblyInterval) are assembled now (an update without a new node does not
  // defer) rather than at the next node.
  void assembleDeferredGrid() {
    if (!grid || grid->pendingUpdates() == 0) return;
    StageTimer t(stats, Statistics::kTimingMap_assembling);
    grid->update(graph.posesOfGroup(mapId));
  }
  // The global grid drops the cells of the nodes that left for the LTM (read back on demand).
  void evictTransferredGrids(const memory::LoopClosureUpdate& u) {
    if (grid) {
      for (int id : u.transferred) grid->evictLocalGrid(id);
    }
  }

  // RtabmapNode.cpp: what a new node is made of.
  memory::LocationInput makeLocation(const SensorData& data, const Transform& odom, const Covariance6& covariance);
  // An intermediate node's: the data per Mem/IntermediateNodeDataKept, no words nor grid.
  memory::LocationInput makeIntermediateLocation(const SensorData& data, const Transform& odom,
                                                 const Covariance6& covariance);
  void extractWords(const SensorData& data, memory::LocationInput& in);
  // Mem/LaserScan* filters on the frame's scan (kept unfiltered, with a warning, if they leave nothing).
  void applyScanFilter(SensorData& data, int frameId) const;
  // What Working Memory and the database keep of a node's data: images decimated
  // (Mem/ImagePostDecimation) and compressed, depth in millimetres (Mem/SaveDepth16Format), raw
  // images dropped unless Mem/ImageKept; the scan stays raw (registrations use it again and again).
  void compressForMemory(SensorData& data) const;
  static SensorData imagesOf(const SensorData& data);
  SensorData imagesForMemory(SensorData images, bool parallel) const;
  void keepImages(SensorData& data, const SensorData& images) const;
  // Id (Mem/GenerateIds false), odometry pose, stamp, map and neighbour-link information.
  void setFrameOf(memory::LocationInput& in, const SensorData& raw, const Transform& odom,
                  const Covariance6& covariance) const;
  void refineNeighborLink(int newId);
  // Rtabmap/CreateIntermediateNodes: the node before the intermediate nodes that end with
  // `previousId`, then them, oldest first ({previousId} if it is no intermediate node; empty if
  // the chain leaves RAM or starts the map).
  std::vector<int> chainToPreviousNode(int previousId) const;
  // The odometry from chain[0] to newId through the chain's neighbour links (covariances summed).
  Link chainOdometry(const std::vector<int>& chain, int newId) const;
  void spreadOverChain(const std::vector<int>& chain, int newId, const Transform& odometry,
                       const Transform& refined, const Link::InfMatrix& information);
  // RGBD/ProximityByTime (ProximityByTime.h): the links added to memory, for the optimisation.
  std::vector<Link> proximityByTime(int newId);
  // Registration of an accepted hypothesis; the link, or nullopt (rejected, reason logged).
  // checkDistance: refuse a link that moves the robot more than RGBD/MaxLoopClosureDistance
  // from where the graph puts it (not before a first localization: the robot is anywhere);
  // such a link is given in `refusedForJump` when not null.
  std::optional<Link> verifyLoopClosure(int newId, int hypothesisId, bool checkDistance,
                                        std::optional<Link>* refusedForJump = nullptr);

  // RtabmapLandmarks.cpp
  // The markers of a frame that comes without landmarks (RGBD/MarkerDetection).
  void detectMarkers(SensorData& data);
  void carryLandmarks(const SensorData& skipped, const Transform& odom);
  // The carried landmarks the frame at `odom` does not see itself, in its base frame.
  void takeCarriedLandmarks(SensorData& data, const Transform& odom);
  // The new node's landmark links to landmarks that other nodes in RAM of the current
  // referential saw too: constraints that close a loop through the landmark. A landmark only
  // another map's nodes saw (orientation measured by both) gives instead a loop closure to the
  // one that saw it nearest, which merges the maps (added to memory here).
  std::vector<Link> landmarkClosures(int newId);
  // Localization mode: for each landmark the temporary node sees that a map node in RAM saw
  // too, a link from the temporary node to the map node that saw it nearest.
  std::vector<Link> landmarkLocalizations(int tempId) const;

  // RtabmapGraph.cpp
  std::map<int, Transform> ramPosesOfGroup() const;
  std::multimap<int, Link> ramLinks(const std::map<int, Transform>& poses) const;
  // Optimises the local map. With new links, drops them again when the result disagrees with
  // them (RGBD/OptimizeMaxError). Returns the links kept.
  std::vector<Link> optimizeLocalMap(int newId, const std::vector<Link>& newLinks);
  OptimizerOptions incrementalOptions(const std::map<int, Transform>& input, const std::vector<Link>& newLinks) const;
  // Links kept this update that join the current map to another one: merge links, and the
  // global ones vote for the merge.
  void recordMergeLinks(const std::vector<Link>& kept);
  // A closure to another map refused for its jump or by the graph votes against the merge;
  // when the vote turns, the merge is undone and redone through the agreeing closures
  // (returned, to optimise).
  std::vector<Link> arbitrateMerge(int newId, const std::optional<Link>& refused);
  std::vector<Link> remerge(const Remerge& r);
  void retrieveNearRobot(const Transform& pose, memory::LoopClosureUpdate& u, std::set<int>& immune);
  std::set<int> localImmunity(const Transform& pose) const;

  // RtabmapInitialPose.cpp
  // Before an update: the user's initial pose, else, in localization before the first update,
  // the last session's last pose (or the origin, RGBD/StartAtOrigin), set map -> odom.
  void applyStartPose(const Transform& odom);
  // The map of the newest node known (-1 if none): the map a new session continues.
  int newestMapId() const;

  // RtabmapPlanning.cpp
  bool setGoal(const PlanGoal& goal);
  void saveGoalInUserData(int goalNodeId);
  // Follows the plan this update: retrieval and immunity of the upcoming path nodes.
  void followPlan(int currentId, memory::LoopClosureUpdate& u, std::set<int>& immune);
};

}  // namespace rtabmap

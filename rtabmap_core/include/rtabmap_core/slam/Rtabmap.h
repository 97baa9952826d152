#pragma once
// RTAB-Map: graph-based SLAM with memory management (Labbé & Michaud: T-RO 2013 for loop
// closure and memory management, IROS 2014 for multi-session, Autonomous Robots 2017 (SPLAM)
// for proximity detection and planning, JFR 2019 for the whole pipeline).
//
//   Rtabmap slam;
//   slam.init(parameters, "~/.ros/rtabmap.db");      // opens or creates the map, new session
//   for (each frame with its odometry) {
//     if (slam.process(data, odomPose, odomCovariance)) {
//       publish(slam.mapCorrection());                // map -> odom
//       const Statistics& s = slam.statistics();      // ids, timings, loop closures
//     }
//   }
//   slam.close();                                     // everything in RAM is saved
//
// One process() call is one update (at most Rtabmap/DetectionRate per second of data stamps):
//   memory update    the node (words, local grid, odometry pose and link) enters STM, or, if
//                    the robot has not moved (RGBD/LinearUpdate, RGBD/AngularUpdate), only
//                    rehearses the previous node and the update stops there;
//   neighbour link   optionally refined by registration (RGBD/NeighborLinkRefining);
//   loop closure     Bayes filter over WM; an accepted hypothesis is linked only if
//                    registration (Reg/Strategy) finds its transform;
//   retrieval        neighbours of the highest hypothesis, and LTM nodes near the robot;
//   proximity        by space (see ProximityBySpace.h) when no loop closure was accepted;
//   optimisation     of the local map (nodes in RAM linked to the current one) when links were
//                    added; the new links are dropped again if the optimised graph disagrees
//                    with them by more than RGBD/OptimizeMaxError standard deviations;
//   map update       map -> odom, the global occupancy grid;
//   transfer         to LTM when the update took more than Rtabmap/TimeThr or WM holds more
//                    than Rtabmap/MemoryThr nodes (never the local map near the robot, the
//                    hypothesis' neighbourhood or what was just retrieved).
//
// Sessions: every init() on an existing database starts a new map; so do triggerNewMap() and
// an odometry reset (identity pose after motion, or a jump beyond RGBD/NewMapOdomChangeDistance).
// A link between two maps merges them into one referential, the oldest one's.
//
// Localization (Mem/IncrementalMemory false): the database is opened read-only; each frame is
// a temporary node used only to localise against the map (loop closure and proximity), then
// forgotten; map -> odom moves by the localisations.
//
// Bad input never throws from process(): it is refused with the reason in lastRejection()
// and a warning (null or non-finite pose, lost odometry, stamps going backwards). init()
// throws ParameterError / DatabaseError.
#include <Eigen/Core>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/maps/GridMap.h"
#include "rtabmap_core/memory/Link.h"
#include "rtabmap_core/memory/Signature.h"
#include "rtabmap_core/params/Parameters.h"
#include "rtabmap_core/slam/Statistics.h"

namespace rtabmap {

// Counts over the life of this Rtabmap (since init()).
struct SlamSummary {
  int updates = 0;            // process() calls
  int nodesAdded = 0;         // nodes created (mapping), intermediate nodes not included
  int intermediateNodes = 0;  // Rtabmap/CreateIntermediateNodes: skipped frames kept as nodes
  int reducedNodes = 0;       // Mem/ReduceGraph: nodes merged into an older one they closed a loop with
  int skippedRate = 0;        // dropped by Rtabmap/DetectionRate
  int skippedStill = 0;       // robot did not move
  int skippedSpeed = 0;       // robot moved faster than RGBD/LinearSpeedUpdate or AngularSpeedUpdate
  int skippedMapStart = 0;    // frames discarded before a map could start (Rtabmap/StartNewMapOn*)
  int refused = 0;            // bad input (see lastRejection())
  int loopClosures = 0;       // global loop closures linked
  int proximityLinks = 0;     // proximity links by space
  int timeLinks = 0;          // proximity links by time (RGBD/ProximityByTime)
  int landmarkClosures = 0;   // landmark links to a landmark an older node saw (loops closed through it)
  int rejectedLinks = 0;      // hypotheses whose registration failed + links undone by OptimizeMaxError
  int localizations = 0;      // localization mode: updates localised on the map
  int mapsStarted = 0;        // maps (sessions) started, the first one included
  int remerges = 0;           // merges with earlier maps undone and redone (MergeArbiter)
  int transferred = 0, retrieved = 0;
  int maxWmSize = 0;
};

// Which parts of a node's sensor data Rtabmap::node() returns (links, words, calibration, GPS
// and the odometry pose always come).
struct NodeDataParts {
  bool images = true;  // RGB / left and depth / right images
  bool scan = true;
  bool grid = true;    // the local occupancy grid
  bool userData = true;
};

class Rtabmap {
 public:
  Rtabmap();
  ~Rtabmap();
  Rtabmap(const Rtabmap&) = delete;
  Rtabmap& operator=(const Rtabmap&) = delete;

  // Opens (creates) the database and starts a session (a new map). databasePath "" = no
  // long-term memory (no transfer or retrieval; nothing saved). Throws ParameterError for an
  // invalid or undeclared parameter, DatabaseError for a database that cannot be used.
  void init(const ParametersMap& parameters, const std::string& databasePath);
  // Saves every node in RAM and the Working Memory state, closes the database.
  void close();
  bool isInitialized() const;

  // One update with this frame and its odometry (pose in the odom frame, 6x6 covariance x y z
  // roll pitch yaw; covariance >= 9999 on the diagonal = odometry lost). Returns true when the
  // frame was used (a node added, merged, or a localisation done).
  bool process(const SensorData& data, const Transform& odomPose,
               const Eigen::Matrix<double, 6, 6>& odomCovariance = Eigen::Matrix<double, 6, 6>::Identity() * 1e-4);
  // Same, with the pose and covariance carried by the data (SensorData::odomPose()).
  bool process(const SensorData& data);

  // Why the last process() refused its input ("" if it did not).
  const std::string& lastRejection() const;
  const Statistics& statistics() const;
  SlamSummary summary() const;

  // map -> odom.
  Transform mapCorrection() const;
  // The robot's pose in the map at the last update (null before the first).
  Transform currentPose() const;
  // Optimised poses of every node of the current referential (nodes in LTM keep the pose they
  // had when they left RAM). Before the first node of a new map, the referential of the
  // database's last node: a new session on an existing database shows the map it continues.
  std::map<int, Transform> optimizedPoses() const;
  // Landmarks (RGBD/MarkerDetection, or given with the input) where the last optimisation that
  // included them put them, by graph id (-landmark id), in the current referential.
  std::map<int, Transform> landmarkPoses() const;
  // Links of the nodes in RAM (each once).
  std::multimap<int, Link> localLinks() const;
  // Every link of the map (database and RAM, each once).
  std::multimap<int, Link> allLinks() const;
  // Odometry pose of each node of the current referential that is known.
  int mapId() const;
  int lastNodeId() const;
  // The newest node of the current map: lastNodeId(), or an intermediate node added since
  // (Rtabmap/CreateIntermediateNodes). 0 before the map's first node.
  int newestNodeId() const;
  std::vector<int> workingMemory() const;  // WM + STM ids

  // Starts a new map (new map id) at the next update, as an odometry reset does.
  void triggerNewMap();
  // The input's clock went back (ROS time jumped back: a bag played again, a simulator reset).
  // The previous stamps are forgotten, so the older ones are accepted again. Mapping: the next
  // update starts a new map, because odometry restarted with the clock (its first pose need not
  // be the identity: the first frames may be lost while tf refills). Localization: the odometry
  // cache is cleared; map -> odom is kept until the next localisation.
  void clockJumpedBack();
  // Where the robot is in the map frame, given by the user (rviz's "2D Pose Estimate", the
  // node's initial_pose) (RtabmapInitialPose.cpp). Localization: the robot is assumed at `pose`
  // until it localises (instead of the last session's last pose, RGBD/StartAtOrigin), so the
  // proximity search and the retrieval from LTM look around it; the next localisation is
  // accepted wherever it puts the robot (RGBD/MaxLoopClosureDistance does not apply to a
  // guess). Mapping: where the current map starts, only before its first node (after init()
  // or a new map). map -> odom becomes pose * odom^-1 at the next update (at once when an
  // odometry pose was already received). False, with the reason in *why, for a null or
  // non-finite pose or a map already started.
  bool setInitialPose(const Transform& pose, std::string* why = nullptr);
  // Labels (goals by name). False if the node is unknown or the label is used by another node.
  bool setLabel(int nodeId, const std::string& label);
  std::map<int, std::string> labels() const;
  // The node with this label, 0 if none.
  int nodeOfLabel(const std::string& label) const;

  // Path planning (SPLAM paper, 3.3.5): a goal as a node id, a label or a pose of the current
  // referential; the topological path is planned at once (Dijkstra over the whole map, LTM
  // included) and followed by the next updates: the farthest path node of the local map within
  // RGBD/LocalRadius is the current metric goal (statistics().currentGoalId), upcoming path
  // nodes are retrieved from LTM and immune from transfer. False, with the reason in
  // lastRejection(), when there is no path (unknown node or label, another referential).
  bool setGoal(int nodeId);
  bool setGoal(const std::string& label);
  bool setGoal(const Transform& pose);
  void cancelGoal();
  // The planned path (node id, pose when planned); empty without an active goal.
  std::vector<std::pair<int, Transform>> goalPath() const;
  // Set by the update that reached the goal / gave up on it (the plan is then over).
  bool goalReached() const;
  const std::string& goalFailure() const;

  // The global occupancy grid (RGBD/CreateOccupancyGrid), assembled from the local grids with
  // the optimised poses of the current referential. Empty without grids.
  GridMap gridMap() const;

  // --- Queries and edits for the ROS interface (RtabmapQueries.cpp) ---
  // A path from the robot to a node, or to a pose of the current referential, planned as
  // setGoal() plans (same planner and options, whole map) but leaving the active goal alone:
  // what a navigation stack asks before deciding. Empty, with the reason in *why, if none.
  std::vector<std::pair<int, Transform>> planPath(int nodeId, std::string* why = nullptr) const;
  std::vector<std::pair<int, Transform>> planPath(const Transform& pose, std::string* why = nullptr) const;

  // A node of the map, from RAM or else the database; getPose() is its odometry pose (the
  // optimised one is in optimizedPoses()). nullopt if no such node.
  std::optional<Signature> node(int id, const NodeDataParts& parts = NodeDataParts()) const;
  // Every node of the database and of RAM, every referential (sorted).
  std::vector<int> allNodeIds() const;

  // A link given by the user (Link::kUserClosure, e.g. "these two places are the same"):
  // between two nodes of the map, brought back from LTM if needed; the local map is
  // re-optimised at once, so map -> odom and the poses follow. False, with the reason in
  // lastRejection(), for an unknown node, a self link, a null transform, localization mode
  // (the map is read-only), or a link the graph rejects (RGBD/OptimizeMaxError).
  bool addLink(const Link& link);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rtabmap

#pragma once
// rtabmap: the SLAM nodelet (also the node `rtabmap`). Feeds synchronised sensor data and
// odometry to the core's Rtabmap and publishes what it maps.
//
// Inputs (rtabmap_sync::DataSubscriber, classic subscribe_* / approx_sync / queue_size):
//   rgb/image + depth/image + rgb/camera_info (subscribe_depth, default), rgbd_image
//   (subscribe_rgbd, one camera), left/image_rect + right/image_rect + their camera_info
//   (subscribe_stereo), or no camera (laser only), with scan or scan_cloud (subscribe_scan / subscribe_scan_cloud), odom
//   (subscribe_odom); without subscribe_odom the odometry is read from tf
//   (odom_frame_id -> frame_id at the data's stamp).
// Parameters:
//   frame_id (base_link), odom_frame_id (odom), map_frame_id (map)
//   database_path (~/.ros/rtabmap.db; "" = no database), config_path (INI of core parameters;
//     private Group/Name parameters override it)
//   database_directory ("" = the directory of database_path): the only directory whose files
//     a service may open, create or delete (load_database); "..", paths elsewhere and symlinks
//     out of it are refused (rtabmap_slam_node/ServicePaths.h)
//   publish_tf (true), tf_delay (0.05 s: period of the map -> odom timer), tf_tolerance
//     (0.1 s: map -> odom is stamped now + tf_tolerance so lookups at slightly later stamps work)
//   wait_for_transform_duration (0.2 s)
//   odom_tf_linear_variance, odom_tf_angular_variance (0.001): covariance of odometry from tf
//   odom_sensor_sync (false): correct each sensor's pose on the robot by the odometry's
//     motion (through tf, odom_frame_id fixed) between the odometry's stamp and the sensor's,
//     for approx_sync inputs on a moving robot (rtabmap_slam_node/OdomSensorSync.h)
//   odom_covariance_cumulative (false): the odom topic's covariance grows from the start
//     (wheel odometry) rather than being the last motion's (rtabmap's odometry); see
//     rtabmap_slam_node/SlamNodeSupport.h motionCovariance()
//   Group/Name: core parameters (strings accepted; an unknown key is warned with the closest)
//   initial_pose ("" = none): "x y z roll pitch yaw" or "x y z qx qy qz qw", the robot's pose
//     in map_frame_id given to the core (Rtabmap::setInitialPose) each time it starts (node
//     start, reset, backup, mode switch, update_parameters, load_database): localization
//     assumes the robot there until it localises, mapping starts the new map there.
// Arguments: -d / --delete_db_on_start deletes the database before opening it.
// Topics in: goal (geometry_msgs/PoseStamped; any frame tf can bring to map_frame_id): plan to
//   the node nearest to the pose and follow it; goal_node (rtabmap_ros/Goal: node_id, or
//   node_label when node_id is 0); initialpose (geometry_msgs/PoseWithCovarianceStamped,
//   rviz's "2D Pose Estimate"; map_frame_id, or a frame tf can bring to it; the covariance is
//   not used): the robot is there now (Rtabmap::setInitialPose; refused, with a warning, in
//   mapping mode once the map has nodes); imu (sensor_msgs/Imu with an orientation, e.g.
//   imu_filter_madgwick's; samples without one are ignored): each frame takes the orientation
//   at its stamp, placed on the robot by tf, and its node a gravity link from it
//   (Optimizer/GravitySigma > 0 uses them; Mem/UseOdomGravity takes the odometry's instead);
//   landmark_detection / landmark_detections (rtabmap_ros/LandmarkDetection(s): another node's
//   fiducial or object detections, pose in the camera's frame): the next frame mapped takes
//   those up to 1 s old, placed on the robot by tf at their stamp and moved by the odometry
//   since, as landmarks of its node (RGBD/MarkerDetection is then not run on that frame).
// Topics out: info (rtabmap_ros/Info), mapGraph (rtabmap_ros/MapGraph), grid_map
//   (nav_msgs/OccupancyGrid, latched, computed only when subscribed), localization_pose
//   (geometry_msgs/PoseWithCovarianceStamped, localization mode), tf map -> odom;
//   goals: mapPath and global_path (nav_msgs/Path, latched: the active goal's path in the map
//     frame with the latest optimised poses of its nodes; empty when there is no goal),
//     global_path_nodes (rtabmap_ros/Path, latched: the same with node ids), goal_reached
//     (std_msgs/Bool: true after the update that reached the goal, false when planning gave up);
//   for stock rviz (latched, computed only when subscribed): labels (MarkerArray,
//     TEXT_VIEW_FACING per label at its node) and graph_markers (MarkerArray: nodes as a
//     SPHERE_LIST, links as one LINE_LIST per kind: neighbor, loop_closure, proximity, user);
//   mapData (rtabmap_ros/MapData, only when subscribed): after each update, the graph and the
//     data of the node that update added (classic incremental map; publish_map sends it all).
//   3D maps (latched; each maintained only while one of its topics has a subscriber, built
//     from the whole map when one appears, then updated incrementally with the optimised
//     poses and published again when an update changed it; Grid/* and GridGlobal/*
//     parameters; rtabmap_slam_node/MapsAssembler.h):
//     cloud_map (sensor_msgs/PointCloud2: every node's obstacle and ground cells, voxel
//     filtered at Grid/CellSize, rgb when the nodes had colour), octomap_binary and
//     octomap_full (rtabmap_ros/OctoMap: octomap_msgs/Octomap's fields, "OcTree" occupancy /
//     "ColorOcTree"), octomap_occupied_space, octomap_obstacles, octomap_ground,
//     octomap_empty_space (PointCloud2 of voxel centres at GridGlobal/OctoMapTreeDepth),
//     occupied_cells_vis_array (visualization_msgs/MarkerArray: occupied voxels as cubes, as
//     octomap_server names it, for rviz without the octomap plugin), octomap_grid
//     (nav_msgs/OccupancyGrid: the octomap projected on the floor). A real 3D octomap needs 3D
//     local grids (Grid/3D with Grid/Sensor 1 or 2); from 2D scans it is one flat layer.
//     Assembled and published by a worker thread, off the SLAM update (which only hands over
//     the poses and the new nodes' grids; updates coming while it is busy coalesce). info
//     carries Maps/Assembling_updates/ (assemblies of a 3D map since start: 0 while nobody
//     listened), Maps/Coalesced_jobs/ (updates merged into a later assembly, since start), and
//     of the last COMPLETED assembly (usually an earlier update's): Maps/Graph_nodes/ (its
//     graph), Maps/Grids_fetched/, Maps/Cloud_nodes/, Maps/OctoMap_nodes/,
//     Maps/OctoMap_rebuilt/, Maps/Time/ms.
// Services: reset, pause, resume, trigger_new_map, backup, set_mode_localization,
//   set_mode_mapping (std_srvs/Empty), get_map (nav_msgs/GetMap), set_label
//   (rtabmap_ros/SetLabel), list_labels (rtabmap_ros/ListLabels), remove_label
//   (rtabmap_ros/RemoveLabel);
//   set_goal (rtabmap_ros/SetGoal: node_id or node_label, frame_id "" or map_frame_id; answers
//   the path and the planning time),
//   cancel_goal (std_srvs/Empty), get_plan (rtabmap_ros/GetPlan: a path from the robot to
//   goal_node or the goal pose without making it the goal; tolerance > 0: the pose must be
//   that close to the path's last node);
//   get_nodes_in_radius (rtabmap_ros/GetNodesInRadius: optimised poses within radius of a node
//   or a position, nearest first; radius <= 0: any distance; k > 0: the k nearest);
//   get_map_data (rtabmap_ros/GetMap: global = every node of the database, else the working
//   memory; optimized = optimised poses (current referential), else odometry poses; graphOnly
//   = no node data), publish_map (rtabmap_ros/PublishMap: the same, published on mapData and
//   the marker topics), get_node_data (rtabmap_ros/GetNodeData: nodes by id with the asked
//   parts; NodeData.pose is the odometry pose);
//   add_link (rtabmap_ros/AddLink: a user link, Link type 4; the map is re-optimised at once),
//   update_parameters (std_srvs/Empty: re-reads config_path and the private Group/Name
//   parameters and restarts the core on the same database, in the same mode unless
//   Mem/IncrementalMemory is among them; a new session starts, as after backup), load_database
//   (rtabmap_ros/LoadDatabase: closes the map, opens database_path, clear = delete it first;
//   database_path relative to database_directory or inside it, else refused before anything
//   is closed or deleted).
// A request that cannot be served (no core, unknown node or label, bad values) answers false
// with a warning saying why.
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nav_msgs/GetMap.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <rtabmap_ros/AddLink.h>
#include <rtabmap_ros/GetMap.h>
#include <rtabmap_ros/GetNodeData.h>
#include <rtabmap_ros/GetNodesInRadius.h>
#include <rtabmap_ros/GetPlan.h>
#include <rtabmap_ros/LandmarkDetection.h>
#include <rtabmap_ros/LandmarkDetections.h>
#include <rtabmap_ros/Goal.h>
#include <rtabmap_ros/ListLabels.h>
#include <rtabmap_ros/LoadDatabase.h>
#include <rtabmap_ros/MapData.h>
#include <rtabmap_ros/PublishMap.h>
#include <rtabmap_ros/RemoveLabel.h>
#include <rtabmap_ros/SetGoal.h>
#include <rtabmap_ros/SetLabel.h>
#include <std_srvs/Empty.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "MapsPublisher.h"
#include "rtabmap_core/slam/Rtabmap.h"
#include "rtabmap_conversions/ImuOrientationBuffer.h"
#include "rtabmap_slam_node/LandmarkBuffer.h"
#include "rtabmap_slam_node/SlamNodeSupport.h"
#include "rtabmap_sync/DataSubscriber.h"
#include "rtabmap_sync/LogThrottle.h"

namespace rtabmap_ros {

class RtabmapNodelet : public nodelet::Nodelet {
 public:
  ~RtabmapNodelet() override;

 private:
  void onInit() override;
  void readNodeParameters(ros::NodeHandle& pnh);
  rtabmap::ParametersMap readCoreParameters(ros::NodeHandle& pnh);
  void applyArguments(const rtabmap_slam_node::NodeArguments& args);  // -d
  void advertise(ros::NodeHandle& nh);
  void subscribe(ros::NodeHandle& nh, ros::NodeHandle& pnh);
  // (Re)starts the core on databasePath_ with parameters_ (+ Mem/IncrementalMemory as
  // `mapping`); false with an error logged when the database or parameters are unusable.
  bool startCore(bool mapping);
  void stopCore();

  void onData(const rtabmap_sync::SyncedData& d);
  // The odometry pose of frame_id and its motion covariance, from the odom message or tf.
  bool odometryOf(const rtabmap_sync::SyncedData& d, rtabmap::Transform* pose, rtabmap_slam_node::Covariance6* cov,
                  std::string* error);
  std::optional<rtabmap::SensorData> makeFrame(const rtabmap_sync::SyncedData& d, std::string* error) const;
  std::optional<rtabmap::LaserScan> makeScan(const rtabmap_sync::SyncedData& d, std::string* error) const;
  rtabmap::Transform sensorPose(const std::string& sensorFrame, const ros::Time& stamp, std::string* error) const;
  // sensorPose(), moved by the odometry between the data's odometry stamp and the sensor's
  // stamp when odom_sensor_sync is on.
  rtabmap::Transform syncedSensorPose(const rtabmap_sync::SyncedData& d, const std::string& sensorFrame,
                                      const ros::Time& stamp, std::string* error) const;
  void publishUpdate(const ros::Time& stamp);
  void publishGrid(const ros::Time& stamp);
  void onTfTimer(const ros::WallTimerEvent&);

  bool onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onResume(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onTriggerNewMap(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onBackup(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onSetModeLocalization(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onSetModeMapping(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onGetMap(nav_msgs::GetMap::Request&, nav_msgs::GetMap::Response& res);
  bool onSetLabel(rtabmap_ros::SetLabel::Request& req, rtabmap_ros::SetLabel::Response&);
  bool onListLabels(rtabmap_ros::ListLabels::Request&, rtabmap_ros::ListLabels::Response& res);
  bool onRemoveLabel(rtabmap_ros::RemoveLabel::Request& req, rtabmap_ros::RemoveLabel::Response&);
  bool onGetNodesInRadius(rtabmap_ros::GetNodesInRadius::Request& req, rtabmap_ros::GetNodesInRadius::Response& res);
  bool onAddLink(rtabmap_ros::AddLink::Request& req, rtabmap_ros::AddLink::Response&);
  bool onUpdateParameters(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onLoadDatabase(rtabmap_ros::LoadDatabase::Request& req, rtabmap_ros::LoadDatabase::Response&);
  // Restarts the core after a change of database or parameters; on failure goes back to
  // `previousPath` and `previousParameters` (the node stays usable) and returns false.
  bool restartCore(const std::string& previousPath, const rtabmap::ParametersMap& previousParameters);

  // Goals (RtabmapGoals.cpp).
  void onGoal(const geometry_msgs::PoseStampedConstPtr& msg);
  void onGoalNode(const rtabmap_ros::GoalConstPtr& msg);
  bool onSetGoal(rtabmap_ros::SetGoal::Request& req, rtabmap_ros::SetGoal::Response& res);
  bool onCancelGoal(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onGetPlan(rtabmap_ros::GetPlan::Request& req, rtabmap_ros::GetPlan::Response& res);
  // Sets a goal on a node (id, or label when id is 0); false with a warning naming why.
  bool setGoalNode(int nodeId, const std::string& label, const char* from);
  // The goal pose in the map frame (tf from the message's frame); null with *error if unknown.
  rtabmap::Transform poseInMap(const geometry_msgs::PoseStamped& goal, std::string* error) const;
  void publishGoalPath(const ros::Time& stamp);
  void publishGoalStatus(const ros::Time& stamp);  // after an update: path and goal_reached

  // Initial pose (RtabmapInputs.cpp): from the initialpose topic, or initial_pose at each
  // start of the core (mutex_ held); logs whether the core took it, and moves map -> odom.
  void onInitialPose(const geometry_msgs::PoseWithCovarianceStampedConstPtr& msg);
  bool applyInitialPose(const rtabmap::Transform& pose, const char* from);
  // IMU orientation (RtabmapInputs.cpp): samples kept without taking mutex_ (an update may
  // hold it for a while); a frame gets the one at its stamp, if any (mutex_ held).
  void onImu(const sensor_msgs::ImuConstPtr& msg);
  void attachImuOrientation(rtabmap::SensorData& frame, const ros::Time& stamp);
  // Landmark detections of another node (RtabmapInputs.cpp): kept without taking mutex_; the
  // next frame gets them in its base frame (mutex_ held).
  void onLandmarkDetection(const rtabmap_ros::LandmarkDetectionConstPtr& msg);
  void onLandmarkDetections(const rtabmap_ros::LandmarkDetectionsConstPtr& msg);
  void addLandmarkDetection(const rtabmap_ros::LandmarkDetection& msg);
  void attachLandmarks(rtabmap::SensorData& frame, const ros::Time& stamp);

  // Map views and map data (RtabmapMapData.cpp).
  void publishMarkers(const ros::Time& stamp, bool force = false);
  void publishLatestNodeData(const ros::Time& stamp);
  // The map as get_map_data / publish_map describe it.
  rtabmap_ros::MapData mapDataOf(bool global, bool optimized, bool graphOnly, const ros::Time& stamp) const;
  bool onGetMapData(rtabmap_ros::GetMap::Request& req, rtabmap_ros::GetMap::Response& res);
  bool onPublishMap(rtabmap_ros::PublishMap::Request& req, rtabmap_ros::PublishMap::Response&);
  bool onGetNodeData(rtabmap_ros::GetNodeData::Request& req, rtabmap_ros::GetNodeData::Response& res);
  // The 3D maps (MapsPublisher.h) of the current map, for their listeners; after an update,
  // and at once for a new listener.
  // Hands the update to the maps worker and returns at once (MapsPublisher.h).
  void publishMaps(const ros::Time& stamp, bool force = false);
  void onMapSubscriber();
  std::optional<rtabmap::LocalGrid> localGridOf(int nodeId) const;
  // False with a warning naming the service when there is no core.
  bool haveCore(const char* service);
  std_msgs::Header mapHeader(const ros::Time& stamp) const;

  std::string frameId_ = "base_link";
  std::string odomFrameId_ = "odom";
  std::string mapFrameId_ = "map";
  std::string databasePath_ = "~/.ros/rtabmap.db";
  std::string serviceDirectory_;  // canonical database_directory; "" = it did not exist
  bool publishTf_ = true;
  double tfDelay_ = 0.05;
  double tfTolerance_ = 0.1;
  double waitForTransform_ = 0.2;
  double odomTfLinearVariance_ = 0.001;
  double odomTfAngularVariance_ = 0.001;
  bool odomCovarianceCumulative_ = false;
  bool odomSensorSync_ = false;
  rtabmap::ParametersMap parameters_;  // core parameters (INI + private), without the mode

  std::mutex mutex_;  // the core and the state below: data callbacks vs services
  std::unique_ptr<rtabmap::Rtabmap> core_;
  bool mapping_ = true;
  bool paused_ = false;
  std::optional<rtabmap_slam_node::Covariance6> previousOdomCovariance_;  // cumulative odometry
  long clockJumpsSeen_ = 0;  // rtabmap_sync's count of ROS time jumping back, as last handled

  std::mutex tfMutex_;  // map -> odom for the timer (never waits on an update)
  rtabmap::Transform mapToOdom_ = rtabmap::Transform::Identity();
  rtabmap_slam_node::MapToOdomStamps tfStamps_;
  rtabmap::Transform lastTfSent_;  // the last map -> odom sent (null: none yet)

  std::unique_ptr<tf2_ros::Buffer> tfBuffer_;
  std::unique_ptr<tf2_ros::TransformListener> tfListener_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tfBroadcaster_;
  ros::Publisher infoPub_, mapGraphPub_, gridMapPub_, localizationPosePub_;
  ros::Publisher mapPathPub_, globalPathPub_, globalPathNodesPub_, goalReachedPub_;
  ros::Publisher labelsPub_, graphMarkersPub_, mapDataPub_;
  MapsPublisher maps_;
  ros::Subscriber goalSub_, goalNodeSub_;
  std::optional<rtabmap::Transform> initialPose_;  // initial_pose
  ros::Subscriber initialPoseSub_;
  rtabmap_conversions::ImuOrientationBuffer imuOrientations_;
  rtabmap_sync::LogThrottle imuWarnings_;  // onImu's own (never called concurrently with itself)
  ros::Subscriber imuSub_;  // after what onImu uses: shut down before they go
  rtabmap_slam_node::LandmarkBuffer landmarkDetections_;
  rtabmap_sync::LogThrottle landmarkWarnings_;  // the landmark callbacks' own
  std::mutex landmarkWarningsMutex_;              // (the two topics' callbacks may run at once)
  ros::Subscriber landmarkSub_, landmarksSub_;    // after what their callbacks use
  bool goalPathShown_ = false;  // the last path published was not empty
  std::vector<ros::ServiceServer> services_;
  ros::WallTimer tfTimer_;
  rtabmap_sync::LogThrottle warnings_;
  rtabmap_sync::DataSubscriber subscriber_;  // last: its callbacks stop before the rest goes
};

}  // namespace rtabmap_ros

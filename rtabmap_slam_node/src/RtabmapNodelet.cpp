// rtabmap nodelet: parameters, the core's life cycle, publishing and the map -> odom timer. Inputs
// are in RtabmapInputs.cpp, services in RtabmapServices.cpp. Interface: RtabmapNodelet.h.
#include "RtabmapNodelet.h"

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <rtabmap_ros/Path.h>
#include <std_msgs/Bool.h>
#include <visualization_msgs/MarkerArray.h>
#include <pluginlib/class_list_macros.hpp>
#include <rtabmap_ros/Info.h>
#include <rtabmap_ros/MapGraph.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <sstream>

#include "rtabmap_conversions/CoreLog.h"
#include "rtabmap_core/memory/ProcessMemory.h"
#include "rtabmap_conversions/GraphConversions.h"
#include "rtabmap_conversions/InfoConversions.h"
#include "rtabmap_conversions/TransformConversions.h"
#include "rtabmap_slam_node/InitialPoseParam.h"
#include "rtabmap_slam_node/ServicePaths.h"
#include "rtabmap_odom/NodeParameters.h"
#include "rtabmap_odom/PrivateParameters.h"

namespace rtabmap_ros {

namespace {

// The node's own private parameters (the others without '/' are warned as unknown).
const std::vector<std::string> kNodeParameters = {
    "frame_id", "odom_frame_id", "map_frame_id", "database_path", "database_directory", "config_path", "publish_tf", "tf_delay",
    "tf_tolerance", "wait_for_transform_duration", "odom_tf_linear_variance", "odom_tf_angular_variance",
    "odom_covariance_cumulative", "odom_sensor_sync", "subscribe_depth", "subscribe_rgb", "subscribe_rgbd",
    "subscribe_stereo", "subscribe_scan", "subscribe_scan_cloud", "subscribe_odom", "subscribe_odom_info",
    "subscribe_user_data", "rgbd_cameras", "approx_sync", "approx_sync_max_interval", "queue_size", "initial_pose",
    "image_transport", "depth_image_transport"};

}  // namespace

RtabmapNodelet::~RtabmapNodelet() {
  tfTimer_.stop();
  maps_.stop();  // joins the maps worker: an assembly under way finishes unpublished
  std::lock_guard<std::mutex> lock(mutex_);
  stopCore();  // everything in RAM goes to the database
}

void RtabmapNodelet::onInit() {
  rtabmap_conversions::routeCoreLogToRosconsole();
  // Images map and unmap instead of fragmenting the heap over hours (issue 10): the process's
  // allocator, set before the first map update.
  if (rtabmap::memory::configureAllocator()) {
    NODELET_DEBUG("%s: malloc mmap threshold fixed at %zu bytes", getName().c_str(), rtabmap::memory::kMmapThreshold);
  }
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  readNodeParameters(pnh);
  parameters_ = readCoreParameters(pnh);
  applyArguments(rtabmap_slam_node::parseNodeArguments(getMyArgv()));
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool mapping = !parameters_.count("Mem/IncrementalMemory") ||
                         rtabmap::Parameters::getBool(parameters_, "Mem/IncrementalMemory");
    parameters_.erase("Mem/IncrementalMemory");  // the mode is mapping_, switched by services
    startCore(mapping);
  }
  advertise(nh);
  subscribe(nh, pnh);
}

void RtabmapNodelet::applyArguments(const rtabmap_slam_node::NodeArguments& args) {
  for (const std::string& a : args.unknown) {
    NODELET_WARN("%s: unknown argument \"%s\" (known: -d, --delete_db_on_start).", getName().c_str(), a.c_str());
  }
  if (!args.deleteDbOnStart || databasePath_.empty()) return;
  if (std::remove(databasePath_.c_str()) == 0) {
    NODELET_INFO("%s: deleted %s (--delete_db_on_start).", getName().c_str(), databasePath_.c_str());
  } else if (errno != ENOENT) {
    NODELET_ERROR("%s: --delete_db_on_start: cannot delete %s: %s", getName().c_str(), databasePath_.c_str(),
                  std::strerror(errno));
  }
}

void RtabmapNodelet::subscribe(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
  // rgb/image + depth/image by default, unless another camera mode is asked for alone.
  rtabmap_sync::SubscribeOptions defaults;
  bool rgbd = false, stereo = false, rgb = false;
  pnh.param("subscribe_rgbd", rgbd, rgbd);
  pnh.param("subscribe_stereo", stereo, stereo);
  pnh.param("subscribe_rgb", rgb, rgb);
  defaults.subscribeDepth = !(rgbd || stereo || rgb);
  const rtabmap_sync::SubscribeOptions options = rtabmap_sync::readSubscribeOptions(pnh, defaults);
  if (options.subscribeRgb) {
    NODELET_ERROR("%s: subscribe_rgb (monocular) is not supported: the SLAM node needs depth or stereo.",
                  getName().c_str());
  }
  std::string error;
  if (!subscriber_.setup(nh, getName(), options, [this](const rtabmap_sync::SyncedData& d) { onData(d); }, &error)) {
    NODELET_FATAL("%s: %s", getName().c_str(), error.c_str());
    return;
  }
  NODELET_INFO("%s: %s -> %s -> %s, odometry from %s, database \"%s\"", getName().c_str(), mapFrameId_.c_str(),
               odomFrameId_.c_str(), frameId_.c_str(), options.subscribeOdom ? "the odom topic" : "tf",
               databasePath_.c_str());
}

void RtabmapNodelet::readNodeParameters(ros::NodeHandle& pnh) {
  pnh.param("frame_id", frameId_, frameId_);
  pnh.param("odom_frame_id", odomFrameId_, odomFrameId_);
  pnh.param("map_frame_id", mapFrameId_, mapFrameId_);
  pnh.param("database_path", databasePath_, databasePath_);
  databasePath_ = rtabmap_slam_node::expandHome(databasePath_);
  std::string directory, why;
  pnh.param("database_directory", directory, directory);
  serviceDirectory_ = rtabmap_slam_node::serviceDirectory(directory, databasePath_, &why).value_or("");
  if (serviceDirectory_.empty()) {
    NODELET_WARN("%s: database_directory: %s; load_database will refuse every path.", getName().c_str(), why.c_str());
  }
  pnh.param("publish_tf", publishTf_, publishTf_);
  pnh.param("tf_delay", tfDelay_, tfDelay_);
  pnh.param("tf_tolerance", tfTolerance_, tfTolerance_);
  pnh.param("wait_for_transform_duration", waitForTransform_, waitForTransform_);
  pnh.param("odom_tf_linear_variance", odomTfLinearVariance_, odomTfLinearVariance_);
  pnh.param("odom_tf_angular_variance", odomTfAngularVariance_, odomTfAngularVariance_);
  pnh.param("odom_covariance_cumulative", odomCovarianceCumulative_, odomCovarianceCumulative_);
  pnh.param("odom_sensor_sync", odomSensorSync_, odomSensorSync_);
  std::string initialPose;
  pnh.param("initial_pose", initialPose, initialPose);
  initialPose_ = rtabmap_slam_node::parseInitialPose(initialPose, &why);
  if (!why.empty()) NODELET_ERROR("%s: initial_pose: %s; ignored.", getName().c_str(), why.c_str());
  if (!(tfDelay_ > 0.0)) {
    NODELET_WARN("%s: tf_delay must be > 0 (got %g); using 0.05 s.", getName().c_str(), tfDelay_);
    tfDelay_ = 0.05;
  }
  if (!(odomTfLinearVariance_ > 0.0) || !(odomTfAngularVariance_ > 0.0)) {
    NODELET_WARN("%s: odom_tf_linear_variance and odom_tf_angular_variance must be > 0; using 0.001.",
                 getName().c_str());
    odomTfLinearVariance_ = odomTfAngularVariance_ = 0.001;
  }
}

rtabmap::ParametersMap RtabmapNodelet::readCoreParameters(ros::NodeHandle& pnh) {
  std::string configPath, error;
  rtabmap::ParametersMap parameters = rtabmap_odom::configFileParameters(pnh, &configPath, &error);
  if (!error.empty()) NODELET_ERROR("%s: config_path: %s; the file is ignored.", getName().c_str(), error.c_str());
  else if (!configPath.empty()) NODELET_INFO("%s: %zu core parameters from %s", getName().c_str(), parameters.size(), configPath.c_str());
  const std::map<std::string, std::string> raw = rtabmap_odom::privateParameters(pnh);
  rtabmap_odom::CoreParameters core = rtabmap_odom::coreParametersFromPrivate(raw);
  std::vector<std::string> warnings = rtabmap_odom::unknownNodeParameters(raw, kNodeParameters);
  warnings.insert(warnings.end(), core.warnings.begin(), core.warnings.end());
  for (const std::string& w : warnings) NODELET_WARN("%s: %s", getName().c_str(), w.c_str());
  for (const auto& [key, value] : core.parameters) {
    NODELET_INFO("%s: %s = %s", getName().c_str(), key.c_str(), value.c_str());
    parameters[key] = value;  // private parameters override the INI file
  }
  return parameters;
}

void RtabmapNodelet::advertise(ros::NodeHandle& nh) {
  tfBuffer_ = std::make_unique<tf2_ros::Buffer>(ros::Duration(30.0));
  tfListener_ = std::make_unique<tf2_ros::TransformListener>(*tfBuffer_);
  tfBroadcaster_ = std::make_unique<tf2_ros::TransformBroadcaster>();
  infoPub_ = nh.advertise<rtabmap_ros::Info>("info", 10);
  mapGraphPub_ = nh.advertise<rtabmap_ros::MapGraph>("mapGraph", 1);
  gridMapPub_ = nh.advertise<nav_msgs::OccupancyGrid>("grid_map", 1, true);
  localizationPosePub_ = nh.advertise<geometry_msgs::PoseWithCovarianceStamped>("localization_pose", 10);
  services_.push_back(nh.advertiseService("reset", &RtabmapNodelet::onReset, this));
  services_.push_back(nh.advertiseService("pause", &RtabmapNodelet::onPause, this));
  services_.push_back(nh.advertiseService("resume", &RtabmapNodelet::onResume, this));
  services_.push_back(nh.advertiseService("trigger_new_map", &RtabmapNodelet::onTriggerNewMap, this));
  services_.push_back(nh.advertiseService("backup", &RtabmapNodelet::onBackup, this));
  services_.push_back(nh.advertiseService("set_mode_localization", &RtabmapNodelet::onSetModeLocalization, this));
  services_.push_back(nh.advertiseService("set_mode_mapping", &RtabmapNodelet::onSetModeMapping, this));
  services_.push_back(nh.advertiseService("get_map", &RtabmapNodelet::onGetMap, this));
  services_.push_back(nh.advertiseService("set_label", &RtabmapNodelet::onSetLabel, this));
  services_.push_back(nh.advertiseService("list_labels", &RtabmapNodelet::onListLabels, this));
  services_.push_back(nh.advertiseService("remove_label", &RtabmapNodelet::onRemoveLabel, this));
  services_.push_back(nh.advertiseService("get_nodes_in_radius", &RtabmapNodelet::onGetNodesInRadius, this));
  services_.push_back(nh.advertiseService("add_link", &RtabmapNodelet::onAddLink, this));
  services_.push_back(nh.advertiseService("update_parameters", &RtabmapNodelet::onUpdateParameters, this));
  services_.push_back(nh.advertiseService("load_database", &RtabmapNodelet::onLoadDatabase, this));
  // Goals
  mapPathPub_ = nh.advertise<nav_msgs::Path>("mapPath", 1, true);
  globalPathPub_ = nh.advertise<nav_msgs::Path>("global_path", 1, true);
  globalPathNodesPub_ = nh.advertise<rtabmap_ros::Path>("global_path_nodes", 1, true);
  goalReachedPub_ = nh.advertise<std_msgs::Bool>("goal_reached", 1);
  goalSub_ = nh.subscribe("goal", 1, &RtabmapNodelet::onGoal, this);
  goalNodeSub_ = nh.subscribe("goal_node", 1, &RtabmapNodelet::onGoalNode, this);
  initialPoseSub_ = nh.subscribe("initialpose", 1, &RtabmapNodelet::onInitialPose, this);
  imuSub_ = nh.subscribe("imu", 100, &RtabmapNodelet::onImu, this);
  landmarkSub_ = nh.subscribe("landmark_detection", 10, &RtabmapNodelet::onLandmarkDetection, this);
  landmarksSub_ = nh.subscribe("landmark_detections", 10, &RtabmapNodelet::onLandmarkDetections, this);
  services_.push_back(nh.advertiseService("set_goal", &RtabmapNodelet::onSetGoal, this));
  services_.push_back(nh.advertiseService("cancel_goal", &RtabmapNodelet::onCancelGoal, this));
  services_.push_back(nh.advertiseService("get_plan", &RtabmapNodelet::onGetPlan, this));
  // Map views and data
  labelsPub_ = nh.advertise<visualization_msgs::MarkerArray>("labels", 1, true);
  graphMarkersPub_ = nh.advertise<visualization_msgs::MarkerArray>("graph_markers", 1, true);
  // A few messages of margin: a map_assembler that misses one misses that node's grid for good.
  mapDataPub_ = nh.advertise<rtabmap_ros::MapData>("mapData", 10);
  maps_.advertise(nh, false, [this] { onMapSubscriber(); });
  services_.push_back(nh.advertiseService("get_map_data", &RtabmapNodelet::onGetMapData, this));
  services_.push_back(nh.advertiseService("publish_map", &RtabmapNodelet::onPublishMap, this));
  services_.push_back(nh.advertiseService("get_node_data", &RtabmapNodelet::onGetNodeData, this));
  if (publishTf_) tfTimer_ = nh.createWallTimer(ros::WallDuration(tfDelay_), &RtabmapNodelet::onTfTimer, this);
}

bool RtabmapNodelet::startCore(bool mapping) {
  rtabmap::ParametersMap parameters = parameters_;
  parameters["Mem/IncrementalMemory"] = mapping ? "true" : "false";
  auto core = std::make_unique<rtabmap::Rtabmap>();
  try {
    core->init(parameters, databasePath_);
  } catch (const std::exception& e) {
    NODELET_ERROR("%s: cannot start SLAM on \"%s\" (%s mode): %s", getName().c_str(), databasePath_.c_str(),
                  mapping ? "mapping" : "localization", e.what());
    core_.reset();
    publishGoalPath(ros::Time::now());  // a goal does not survive the core
    return false;
  }
  core_ = std::move(core);
  try {
    maps_.setParameters(parameters);  // also drops the maps of the previous core
  } catch (const std::exception& e) {
    // The core accepted them, so this should not happen: the maps keep their options.
    NODELET_ERROR("%s: 3D maps: %s", getName().c_str(), e.what());
    maps_.clear();
  }
  mapping_ = mapping;
  previousOdomCovariance_.reset();
  if (initialPose_) applyInitialPose(*initialPose_, "initial_pose");
  publishGoalPath(ros::Time::now());
  NODELET_INFO("%s: SLAM started in %s mode on \"%s\"", getName().c_str(), mapping ? "mapping" : "localization",
               databasePath_.c_str());
  return true;
}

void RtabmapNodelet::stopCore() {
  if (!core_) return;
  try {
    core_->close();
  } catch (const std::exception& e) {
    NODELET_ERROR("%s: closing the database: %s", getName().c_str(), e.what());
  }
  core_.reset();
  // The maps belong to the core's graph: without it they would stay latched (a failed restart
  // on another database would keep showing the old map as if it were current).
  maps_.clear();
}

void RtabmapNodelet::onData(const rtabmap_sync::SyncedData& d) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (paused_ || !core_) return;
  if (d.clockJumps != clockJumpsSeen_) {
    // A restarted bag or simulator: its stamps start over, and so does its odometry.
    clockJumpsSeen_ = d.clockJumps;
    previousOdomCovariance_.reset();
    imuOrientations_.clear();
    landmarkDetections_.clear();
    core_->clockJumpedBack();
  }
  std::string error;
  rtabmap::Transform odomPose;
  rtabmap_slam_node::Covariance6 covariance;
  std::optional<rtabmap::SensorData> frame;
  if (odometryOf(d, &odomPose, &covariance, &error)) frame = makeFrame(d, &error);
  if (frame) {
    attachImuOrientation(*frame, d.stamp);
    attachLandmarks(*frame, d.stamp);
  }
  if (!frame) {
    if (warnings_.due(rtabmap_odom::throttleKey(error))) {
      NODELET_WARN("%s: %s; data at %.6f ignored.", getName().c_str(), error.c_str(), d.stamp.toSec());
    }
    return;
  }
  bool used = false;
  try {
    used = core_->process(*frame, odomPose, covariance);
  } catch (const std::exception& e) {
    // The core refuses bad input through lastRejection(); an exception is a fault (e.g. the
    // database): reported, and the node keeps running with what the core still holds.
    if (warnings_.due(rtabmap_odom::throttleKey(e.what()))) {
      NODELET_ERROR("%s: SLAM update at %.6f failed: %s", getName().c_str(), d.stamp.toSec(), e.what());
    }
    return;
  }
  if (!core_->lastRejection().empty()) {
    if (warnings_.due(rtabmap_odom::throttleKey(core_->lastRejection()))) {
      NODELET_WARN("%s: data at %.6f refused: %s", getName().c_str(), d.stamp.toSec(),
                   core_->lastRejection().c_str());
    }
    return;
  }
  {
    std::lock_guard<std::mutex> tfLock(tfMutex_);
    mapToOdom_ = core_->mapCorrection();
  }
  if (used) publishUpdate(d.stamp);
}

void RtabmapNodelet::publishUpdate(const ros::Time& stamp) {
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = mapFrameId_;
  publishMaps(stamp);  // first: the worker assembles while the rest is published
  if (infoPub_.getNumSubscribers() > 0) {
    rtabmap_ros::Info info = rtabmap_conversions::statisticsToMsg(core_->statistics(), header);
    maps_.addStatistics(info);  // the maps worker's last completed assembly
    // Input lost since start (rtabmap_sync's DropCounter): the subscriber queues overflowing
    // while an update ran, messages never paired, and the data sets that cost.
    const std::pair<const char*, long> lost[] = {{"Sync/Sets_lost/", subscriber_.setsLost()},
                                                 {"Sync/Missing_from_stamps/", subscriber_.missingFromStamps()},
                                                 {"Sync/Dropped_in_sync/", subscriber_.droppedInSync()}};
    for (const auto& [key, value] : lost) {
      info.statsKeys.push_back(key);
      info.statsValues.push_back(static_cast<float>(value));
    }
    infoPub_.publish(info);
  }
  if (mapGraphPub_.getNumSubscribers() > 0) {
    // The landmarks (markers, RGBD/MarkerDetection) with the nodes, by their negative ids, as the
    // original's mapGraph has them: rviz draws them where the links to them end.
    std::map<int, rtabmap::Transform> poses = core_->optimizedPoses();
    const std::map<int, rtabmap::Transform> landmarks = core_->landmarkPoses();
    poses.insert(landmarks.begin(), landmarks.end());
    mapGraphPub_.publish(rtabmap_conversions::mapGraphToMsg(poses, core_->allLinks(), core_->mapCorrection(), header));
  }
  if (gridMapPub_.getNumSubscribers() > 0) publishGrid(stamp);
  publishGoalStatus(stamp);
  publishMarkers(stamp);
  if (mapDataPub_.getNumSubscribers() > 0) publishLatestNodeData(stamp);
  if (!mapping_ && localizationPosePub_.getNumSubscribers() > 0 && core_->statistics().loopClosureId +
                                                                           core_->statistics().proximityDetectionId > 0) {
    // Localised on the map by this update: where the robot is in the map.
    geometry_msgs::PoseWithCovarianceStamped pose;
    pose.header = header;
    pose.pose.pose = rtabmap_conversions::transformToPoseMsg(core_->currentPose());
    localizationPosePub_.publish(pose);
  }
}

void RtabmapNodelet::publishGrid(const ros::Time& stamp) {
  const rtabmap::GridMap grid = core_->gridMap();
  if (grid.empty()) return;
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = mapFrameId_;
  gridMapPub_.publish(rtabmap_slam_node::gridMapToMsg(grid, header));
}

void RtabmapNodelet::onTfTimer(const ros::WallTimerEvent&) {
  const ros::Time now = ros::Time::now();
  if (now.isZero()) return;  // simulated time not started yet
  geometry_msgs::TransformStamped t;
  // Stamped ahead so lookups at data stamps a little after now still find map -> odom.
  t.header.stamp = now + ros::Duration(tfTolerance_);
  t.header.frame_id = mapFrameId_;
  t.child_frame_id = odomFrameId_;
  {
    std::lock_guard<std::mutex> lock(tfMutex_);
    const std::optional<ros::Time> stamp = tfStamps_.next(t.header.stamp, !(mapToOdom_ == lastTfSent_));
    if (!stamp) return;
    t.header.stamp = *stamp;
    lastTfSent_ = mapToOdom_;
    t.transform = rtabmap_conversions::transformToMsg(mapToOdom_);
  }
  tfBroadcaster_->sendTransform(t);
}

}  // namespace rtabmap_ros

PLUGINLIB_EXPORT_CLASS(rtabmap_ros::RtabmapNodelet, nodelet::Nodelet)

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
//   publish_tf (true), tf_delay (0.05 s: period of the map -> odom timer), tf_tolerance
//     (0.1 s: map -> odom is stamped now + tf_tolerance so lookups at slightly later stamps work)
//   wait_for_transform_duration (0.2 s)
//   odom_tf_linear_variance, odom_tf_angular_variance (0.001): covariance of odometry from tf
//   odom_covariance_cumulative (false): the odom topic's covariance grows from the start
//     (wheel odometry) rather than being the last motion's (rtabmap's odometry); see
//     rtabmap_slam_node/SlamNodeSupport.h motionCovariance()
//   Group/Name: core parameters (strings accepted; an unknown key is warned with the closest)
// Arguments: -d / --delete_db_on_start deletes the database before opening it.
// Topics out: info (rtabmap_ros/Info), mapGraph (rtabmap_ros/MapGraph), grid_map
//   (nav_msgs/OccupancyGrid, latched, computed only when subscribed), localization_pose
//   (geometry_msgs/PoseWithCovarianceStamped, localization mode), tf map -> odom.
// Services: reset, pause, resume, trigger_new_map, backup, set_mode_localization,
//   set_mode_mapping (std_srvs/Empty), get_map (nav_msgs/GetMap), set_label
//   (rtabmap_ros/SetLabel), list_labels (rtabmap_ros/ListLabels).
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nav_msgs/GetMap.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <rtabmap_ros/ListLabels.h>
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

#include "rtabmap_core/slam/Rtabmap.h"
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

  std::string frameId_ = "base_link";
  std::string odomFrameId_ = "odom";
  std::string mapFrameId_ = "map";
  std::string databasePath_ = "~/.ros/rtabmap.db";
  bool publishTf_ = true;
  double tfDelay_ = 0.05;
  double tfTolerance_ = 0.1;
  double waitForTransform_ = 0.2;
  double odomTfLinearVariance_ = 0.001;
  double odomTfAngularVariance_ = 0.001;
  bool odomCovarianceCumulative_ = false;
  rtabmap::ParametersMap parameters_;  // core parameters (INI + private), without the mode

  std::mutex mutex_;  // the core and the state below: data callbacks vs services
  std::unique_ptr<rtabmap::Rtabmap> core_;
  bool mapping_ = true;
  bool paused_ = false;
  std::optional<rtabmap_slam_node::Covariance6> previousOdomCovariance_;  // cumulative odometry

  std::mutex tfMutex_;  // map -> odom for the timer (never waits on an update)
  rtabmap::Transform mapToOdom_ = rtabmap::Transform::Identity();
  ros::Time lastTfStamp_;  // of the last map -> odom sent

  std::unique_ptr<tf2_ros::Buffer> tfBuffer_;
  std::unique_ptr<tf2_ros::TransformListener> tfListener_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tfBroadcaster_;
  ros::Publisher infoPub_, mapGraphPub_, gridMapPub_, localizationPosePub_;
  std::vector<ros::ServiceServer> services_;
  ros::WallTimer tfTimer_;
  rtabmap_sync::LogThrottle warnings_;
  rtabmap_sync::DataSubscriber subscriber_;  // last: its callbacks stop before the rest goes
};

}  // namespace rtabmap_ros

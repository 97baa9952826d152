#pragma once
// The shared synchroniser of the sync, odometry and SLAM nodelets: subscribes to the topics
// selectTopics() picks (SyncTopics.h), pairs them with a message_filters policy (ExactTime or
// ApproximateTime with approx_sync_max_interval), and hands each synchronised set to the node
// as typed messages. It also
//  - drops a message whose stamp is not after the previous one on the same topic (out of
//    order or duplicated), with an error naming the topic: the policies assume ordered input;
//  - logs the "did not receive data since 5 seconds" warning (SyncTopics.h, noDataWarning)
//    when no set came out for 5 s, listing each topic, the policy and what arrived;
//  - counts and warns about input lost silently by message_filters and roscpp's subscriber
//    queues (DropCounter.h).
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rtabmap_ros/OdomInfo.h>
#include <rtabmap_ros/RGBDImage.h>
#include <rtabmap_ros/RGBDImages.h>
#include <rtabmap_ros/UserData.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rtabmap_sync/SyncTopics.h"

namespace rtabmap_sync {

// One synchronised set; the members of the subscribed topics are set, the others null.
struct SyncedData {
  sensor_msgs::ImageConstPtr rgb, depth;
  sensor_msgs::CameraInfoConstPtr rgbCameraInfo;
  sensor_msgs::ImageConstPtr left, right;
  sensor_msgs::CameraInfoConstPtr leftCameraInfo, rightCameraInfo;
  std::vector<rtabmap_ros::RGBDImageConstPtr> rgbdImages;  // rgbd_image, or rgbd_image0..N-1
  rtabmap_ros::RGBDImagesConstPtr rgbdImagesMsg;           // rgbd_cameras = 0
  sensor_msgs::LaserScanConstPtr scan;
  sensor_msgs::PointCloud2ConstPtr scanCloud;
  nav_msgs::OdometryConstPtr odom;
  rtabmap_ros::OdomInfoConstPtr odomInfo;
  rtabmap_ros::UserDataConstPtr userData;
  ros::Time stamp;  // stamp of the first topic (the camera when there is one)
  // Times ROS time was seen jumping back (a restarted bag) before this set: a change tells the
  // node that its input started over (the SLAM core starts a new map, odometry resets).
  long clockJumps = 0;
};

// subscribe_*, rgbd_cameras, approx_sync, approx_sync_max_interval and queue_size from the
// private parameters, `defaults` for those not set.
SubscribeOptions readSubscribeOptions(const ros::NodeHandle& pnh, const SubscribeOptions& defaults = {});

class DataSubscriber {
 public:
  using Callback = std::function<void(const SyncedData&)>;

  DataSubscriber();
  ~DataSubscriber();
  DataSubscriber(const DataSubscriber&) = delete;
  DataSubscriber& operator=(const DataSubscriber&) = delete;

  // Subscribes in `nh` (topics relative to it) and starts the 5-second watch. `name` prefixes
  // the log lines. Returns false (and *error) when the options select no valid topic set.
  bool setup(ros::NodeHandle& nh, const std::string& name, const SubscribeOptions& options,
             const Callback& callback, std::string* error = nullptr);

  // Resolved topic names, in selectTopics() order.
  std::vector<std::string> topics() const;
  const SubscribeOptions& options() const { return options_; }
  // The warning text for the current state (what the 5-second watch logs).
  std::string warningText(double seconds) const;

  // Sets delivered, and messages dropped for their stamp (unset, out of order, duplicated).
  long delivered() const;
  long droppedBadStamps() const;
  // Input lost while the node ran (see DropCounter.h): messages accepted but never in a set,
  // messages missing from each topic's stamps (the subscriber queue overflowed while the node
  // was busy, or the sensor skipped), and the sets that cost, estimated. Logged as a warning
  // (throttled) when they grow.
  long droppedInSync() const;
  long missingFromStamps() const;
  long setsLost() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  SubscribeOptions options_;
};

}  // namespace rtabmap_sync

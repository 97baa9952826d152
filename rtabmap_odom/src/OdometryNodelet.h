#pragma once
// What rgbd_odometry, stereo_odometry and icp_odometry share: parameters, the core odometry,
// the motion guess from tf, publishing (odom, tf, odom_info, odom_local_map, odom_last_frame),
// lost handling and the services. Each nodelet only says which topics it synchronises and how
// a synchronised set becomes a core frame.
//
// Parameters (classic rtabmap_ros names):
//   frame_id (base_link)            robot base frame: the odometry pose is the pose of this frame
//   odom_frame_id (odom)            fixed frame of the odometry
//   publish_tf (true)               publish odom_frame_id -> frame_id (or -> guess_frame_id)
//   guess_frame_id ("")             fixed frame of another odometry (wheels) in tf: its motion of
//                                   frame_id since the previous frame is the motion guess, and
//                                   the tf published is odom_frame_id -> guess_frame_id
//   wait_for_transform_duration (0.2)  s to wait for a tf (sensor mounting, guess)
//   publish_null_when_lost (true)   when lost, publish odom with a null pose and 9999 covariance
//   expected_update_rate (0)        Hz; warn when odometry updates slower than 80 % of it
//   max_update_rate (0)             Hz; process at most this rate of frames (data stamps)
//   wait_imu_to_init (false)        drop frames until one can carry an orientation from the imu
//                                   topic, so odometry starts levelled by it
//   subscribe_*, approx_sync, approx_sync_max_interval, queue_size, rgbd_cameras: the topics
//   Group/Name                      core parameters (Odom/Strategy, Vis/MinInliers, Icp/...)
// Topic in besides the synchronised ones: imu (sensor_msgs/Imu): with an orientation (a filter's
// output such as imu_filter_madgwick's) each frame carries the orientation at its stamp, which
// levels the first pose and gives the motion guess its rotation; without one, the gyroscope's
// rotation between two frames is the guess's (rtabmap_core Odometry.h).
// Topics out: odom (nav_msgs/Odometry), odom_info (rtabmap_ros/OdomInfo), odom_local_map and
// odom_last_frame (sensor_msgs/PointCloud2, odometry frame), tf.
// Services: reset_odom, pause_odom, resume_odom (std_srvs/Empty), reset_odom_to_pose
// (rtabmap_ros/ResetPose).
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <rtabmap_ros/ResetPose.h>
#include <std_srvs/Empty.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "rtabmap_conversions/ImuOrientationBuffer.h"
#include "rtabmap_core/odometry/Odometry.h"
#include "rtabmap_odom/OdometryOutputs.h"
#include "rtabmap_sync/DataSubscriber.h"
#include "rtabmap_sync/LogThrottle.h"

namespace rtabmap_ros {

class OdometryNodelet : public nodelet::Nodelet {
 public:
  ~OdometryNodelet() override;

 protected:
  // lidar: S2M / S2S instead of F2M / F2F. Log lines start with the nodelet's name.
  explicit OdometryNodelet(bool lidar);

  // Topics before the private subscribe_* parameters override them.
  virtual rtabmap_sync::SubscribeOptions defaultSubscribeOptions() const = 0;
  // The nodelet's own private parameters (read before the odometry is made; may adjust the
  // core parameters) and their names (for the unknown-parameter warnings).
  virtual void readParameters(ros::NodeHandle& /*pnh*/, rtabmap::ParametersMap& /*core*/) {}
  virtual std::vector<std::string> parameterNames() const { return {}; }
  // The core frame of a synchronised set, with the sensors' local transforms (sensorPose());
  // nullopt and *error (naming the topic and the problem) on bad input or a missing tf.
  virtual std::optional<rtabmap::SensorData> makeFrame(const rtabmap_sync::SyncedData& d, std::string* error) = 0;
  // The frame's points in the base frame, for odom_last_frame.
  virtual rtabmap::LaserScan frameCloud(const rtabmap::SensorData& frame) const = 0;

  // The pose of sensorFrame in frame_id at `stamp` (the sensor's mounting), waiting up to
  // wait_for_transform_duration; null with *error naming the frames otherwise.
  rtabmap::Transform sensorPose(const std::string& sensorFrame, const ros::Time& stamp, std::string* error) const;

  const tf2::BufferCore& tfBuffer() const { return *tfBuffer_; }
  const std::string& guessFrameId() const { return guessFrameId_; }
  double waitForTransform() const { return waitForTransform_; }
  // The odometry's last motion of frame_id and the seconds it took (null before the first
  // motion and after a reset; kept through lost frames): the constant-velocity model of the
  // current frame's sweep.
  // The base's rotation from t0 to t1 the imu topic's gyroscope measured (samples up to the
  // frame being made); none when they do not cover it. Called from makeFrame.
  std::optional<Eigen::Matrix3d> imuRotationBetween(double t0, double t1) const {
    return odometry_->imuRotationBetween(t0, t1);
  }
  const rtabmap::Transform& lastMotion(double* interval) const {
    *interval = lastInterval_;
    return lastMotion_;
  }

 private:
  void onInit() final;
  void readNodeParameters(ros::NodeHandle& pnh);
  rtabmap::ParametersMap readCoreParameters(ros::NodeHandle& pnh);
  // tf, publishers, services and the update-rate watch.
  void advertise(ros::NodeHandle& nh);
  void createOdometry(const rtabmap::ParametersMap& parameters);
  void onData(const rtabmap_sync::SyncedData& d);
  // The wheel-odometry motion of frame_id since the previous frame (null: none or no tf), and
  // the pose of frame_id in guess_frame_id now (for the tf correction).
  rtabmap::Transform guessMotion(const ros::Time& stamp, rtabmap::Transform* guessPose);
  void publish(const rtabmap::SensorData& frame, const rtabmap::Transform& pose, const rtabmap::OdometryInfo& info,
               const ros::Time& stamp, const rtabmap::Transform& guessPose);
  // odom -> frame_id, or odom -> guess_frame_id with a guess (see guessFrameCorrection).
  void publishTf(const rtabmap::Transform& pose, const rtabmap::Transform& guessPose, const std_msgs::Header& header);
  // Pose with covariance, and the twist of the motion since the previous frame.
  nav_msgs::Odometry odomMessage(const rtabmap::Transform& pose, const rtabmap::OdometryInfo& info,
                                 const std_msgs::Header& header) const;
  void publishClouds(const rtabmap::SensorData& frame, const rtabmap::Transform& pose, const std_msgs::Header& header);
  void reportLost(const rtabmap::OdometryInfo& info, const ros::Time& stamp);
  void resetTo(const rtabmap::Transform& pose);
  void resetLocked(const rtabmap::Transform& pose);  // mutex_ held
  bool onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onResetToPose(rtabmap_ros::ResetPose::Request& req, rtabmap_ros::ResetPose::Response&);
  bool onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onResume(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  void onRateWatch(const ros::WallTimerEvent&);
  void onImu(const sensor_msgs::ImuConstPtr& msg);
  // Gives the frame the imu topic's orientation at its stamp; false when the frame must wait
  // for one (wait_imu_to_init, before the first frame).
  bool attachImuOrientation(rtabmap::SensorData& frame, const ros::Time& stamp);
  // Gives the odometry the angular velocities received since the last frame (mutex_ held).
  void handOverGyroSamples();

  const bool lidar_;
  std::string frameId_ = "base_link";
  std::string odomFrameId_ = "odom";
  std::string guessFrameId_;
  bool publishTf_ = true;
  bool publishNullWhenLost_ = true;
  double waitForTransform_ = 0.2;
  double expectedUpdateRate_ = 0.0;
  bool waitImuToInit_ = false;

  std::mutex mutex_;  // odometry state: data callbacks vs services
  std::unique_ptr<rtabmap::Odometry> odometry_;
  bool paused_ = false;
  ros::Time previousStamp_;  // stamp of the previous processed frame (for the guess)
  rtabmap::Transform lastMotion_;  // see lastMotion()
  double lastInterval_ = 0.0;
  long clockJumpsSeen_ = 0;  // rtabmap_sync's count of ROS time jumping back, as last handled
  rtabmap_odom::UpdateRateLimiter limiter_;
  int updatesSinceWatch_ = 0;
  ros::WallTime lastWatch_;

  std::unique_ptr<tf2_ros::Buffer> tfBuffer_;
  std::unique_ptr<tf2_ros::TransformListener> tfListener_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tfBroadcaster_;
  ros::Publisher odomPub_, odomInfoPub_, localMapPub_, lastFramePub_;
  std::vector<ros::ServiceServer> services_;
  ros::WallTimer rateWatch_;
  rtabmap_sync::LogThrottle errors_;
  rtabmap_conversions::ImuOrientationBuffer imuOrientations_;
  struct PendingGyro {
    ros::Time stamp;
    std::string frameId;
    rtabmap::IMU imu;
  };
  static constexpr size_t kMaxPendingGyro = 2000;  // 5 s at 400 Hz: odometry stopped or paused
  std::mutex gyroMutex_;
  std::vector<PendingGyro> pendingGyro_;  // onImu -> the next frame
  rtabmap_sync::LogThrottle imuWarnings_;  // onImu's own (never called concurrently with itself)
  ros::Subscriber imuSub_;  // after what onImu uses: shut down before they go
  rtabmap_sync::DataSubscriber subscriber_;  // last: its callbacks stop before the rest goes
};

}  // namespace rtabmap_ros

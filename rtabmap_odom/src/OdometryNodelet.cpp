#include "OdometryNodelet.h"

#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>

#include <cctype>
#include <cmath>
#include <map>
#include <sstream>

#include "rtabmap_conversions/CoreLog.h"
#include "rtabmap_conversions/OdomInfoConversions.h"
#include "rtabmap_conversions/OdometryConversions.h"
#include "rtabmap_conversions/PointCloudConversions.h"
#include "rtabmap_conversions/TfLookup.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/odometry/OdometryF2M.h"
#include "rtabmap_core/odometry/OdometryS2M.h"
#include "rtabmap_odom/NodeParameters.h"
#include "rtabmap_odom/PrivateParameters.h"

namespace rtabmap_ros {

namespace {

// The names of the private parameters every odometry node reads.
const std::vector<std::string> kCommonParameters = {
    "frame_id", "odom_frame_id", "publish_tf", "guess_frame_id", "wait_for_transform_duration",
    "publish_null_when_lost", "expected_update_rate", "max_update_rate", "subscribe_depth", "subscribe_rgb",
    "subscribe_rgbd", "subscribe_stereo", "subscribe_scan", "subscribe_scan_cloud", "subscribe_odom_info",
    "subscribe_user_data", "subscribe_odom", "rgbd_cameras", "approx_sync", "approx_sync_max_interval",
    "queue_size", "config_path", "image_transport", "depth_image_transport", "wait_imu_to_init"};

rtabmap::Odometry::Type odometryType(const rtabmap::ParametersMap& parameters, bool lidar) {
  const bool frameToFrame =
      rtabmap::Parameters::getInt(parameters, rtabmap::Parameters::kOdomStrategy()) == 1;
  using T = rtabmap::Odometry::Type;
  return lidar ? (frameToFrame ? T::kS2S : T::kS2M) : (frameToFrame ? T::kF2F : T::kF2M);
}

}  // namespace

OdometryNodelet::OdometryNodelet(bool lidar) : lidar_(lidar) {}

OdometryNodelet::~OdometryNodelet() { rateWatch_.stop(); }

void OdometryNodelet::onInit() {
  rtabmap_conversions::routeCoreLogToRosconsole();
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  readNodeParameters(pnh);
  rtabmap::ParametersMap core = readCoreParameters(pnh);
  readParameters(pnh, core);
  createOdometry(core);
  advertise(nh);

  const rtabmap_sync::SubscribeOptions options = rtabmap_sync::readSubscribeOptions(pnh, defaultSubscribeOptions());
  std::string error;
  if (!subscriber_.setup(nh, getName(), options, [this](const rtabmap_sync::SyncedData& d) { onData(d); }, &error)) {
    NODELET_FATAL("%s", error.c_str());
    return;
  }
  NODELET_INFO("%s: %s odometry, %s -> %s%s%s", getName().c_str(),
               rtabmap::Odometry::typeName(odometry_->type()).c_str(), odomFrameId_.c_str(), frameId_.c_str(),
               guessFrameId_.empty() ? "" : ", guess from tf ", guessFrameId_.c_str());
}

void OdometryNodelet::readNodeParameters(ros::NodeHandle& pnh) {
  pnh.param("frame_id", frameId_, frameId_);
  pnh.param("odom_frame_id", odomFrameId_, odomFrameId_);
  pnh.param("guess_frame_id", guessFrameId_, guessFrameId_);
  pnh.param("publish_tf", publishTf_, publishTf_);
  pnh.param("publish_null_when_lost", publishNullWhenLost_, publishNullWhenLost_);
  pnh.param("wait_for_transform_duration", waitForTransform_, waitForTransform_);
  pnh.param("expected_update_rate", expectedUpdateRate_, expectedUpdateRate_);
  pnh.param("wait_imu_to_init", waitImuToInit_, waitImuToInit_);
  double maxUpdateRate = 0.0;
  pnh.param("max_update_rate", maxUpdateRate, maxUpdateRate);
  limiter_ = rtabmap_odom::UpdateRateLimiter(maxUpdateRate);
  if (!guessFrameId_.empty() && (guessFrameId_ == odomFrameId_ || guessFrameId_ == frameId_)) {
    NODELET_ERROR("%s: guess_frame_id \"%s\" must differ from odom_frame_id and frame_id; no guess used.",
                  getName().c_str(), guessFrameId_.c_str());
    guessFrameId_.clear();
  }
}

void OdometryNodelet::advertise(ros::NodeHandle& nh) {
  tfBuffer_ = std::make_unique<tf2_ros::Buffer>(ros::Duration(30.0));
  tfListener_ = std::make_unique<tf2_ros::TransformListener>(*tfBuffer_);
  tfBroadcaster_ = std::make_unique<tf2_ros::TransformBroadcaster>();
  odomPub_ = nh.advertise<nav_msgs::Odometry>("odom", 10);
  odomInfoPub_ = nh.advertise<rtabmap_ros::OdomInfo>("odom_info", 10);
  localMapPub_ = nh.advertise<sensor_msgs::PointCloud2>("odom_local_map", 1);
  lastFramePub_ = nh.advertise<sensor_msgs::PointCloud2>("odom_last_frame", 1);
  imuSub_ = nh.subscribe("imu", 100, &OdometryNodelet::onImu, this);
  services_.push_back(nh.advertiseService("reset_odom", &OdometryNodelet::onReset, this));
  services_.push_back(nh.advertiseService("reset_odom_to_pose", &OdometryNodelet::onResetToPose, this));
  services_.push_back(nh.advertiseService("pause_odom", &OdometryNodelet::onPause, this));
  services_.push_back(nh.advertiseService("resume_odom", &OdometryNodelet::onResume, this));
  if (expectedUpdateRate_ > 0.0) {
    lastWatch_ = ros::WallTime::now();
    rateWatch_ = nh.createWallTimer(ros::WallDuration(5.0), &OdometryNodelet::onRateWatch, this);
  }
}

rtabmap::ParametersMap OdometryNodelet::readCoreParameters(ros::NodeHandle& pnh) {
  std::vector<std::string> odd;
  const std::map<std::string, std::string> raw = rtabmap_odom::privateParameters(pnh, &odd);
  for (const std::string& name : odd) {
    NODELET_WARN("%s: parameter \"%s\" ignored: not a bool, number or string.", getName().c_str(), name.c_str());
  }
  rtabmap_odom::CoreParameters core = rtabmap_odom::coreParametersFromPrivate(raw);
  std::vector<std::string> known = kCommonParameters;
  for (const std::string& n : parameterNames()) known.push_back(n);
  std::vector<std::string> warnings = rtabmap_odom::unknownNodeParameters(raw, known);
  warnings.insert(warnings.end(), core.warnings.begin(), core.warnings.end());
  for (const std::string& w : warnings) NODELET_WARN("%s: %s", getName().c_str(), w.c_str());
  std::string configPath, error;
  rtabmap::ParametersMap parameters = rtabmap_odom::configFileParameters(pnh, &configPath, &error);
  if (!error.empty()) NODELET_ERROR("%s: config_path: %s; the file is ignored.", getName().c_str(), error.c_str());
  else if (!configPath.empty()) NODELET_INFO("%s: %zu core parameters from %s", getName().c_str(), parameters.size(), configPath.c_str());
  for (const auto& [key, value] : core.parameters) {
    NODELET_INFO("%s: %s = %s", getName().c_str(), key.c_str(), value.c_str());
    parameters[key] = value;  // private parameters override the INI file
  }
  return parameters;
}

void OdometryNodelet::createOdometry(const rtabmap::ParametersMap& parameters) {
  try {
    odometry_ = rtabmap::Odometry::create(odometryType(parameters, lidar_), parameters);
  } catch (const rtabmap::Error& e) {
    // Each value was valid alone, but not together: run with the defaults rather than not at all.
    NODELET_ERROR("%s: %s; using the default odometry parameters.", getName().c_str(), e.what());
    odometry_ = rtabmap::Odometry::create(odometryType({}, lidar_), {});
  }
}

rtabmap::Transform OdometryNodelet::sensorPose(const std::string& sensorFrame, const ros::Time& stamp,
                                               std::string* error) const {
  if (sensorFrame.empty()) {
    if (error) *error = "the message has no frame_id";
    return rtabmap::Transform();
  }
  return rtabmap_conversions::lookupTransform(*tfBuffer_, frameId_, sensorFrame, stamp, waitForTransform_, error);
}

rtabmap::Transform OdometryNodelet::guessMotion(const ros::Time& stamp, rtabmap::Transform* guessPose) {
  if (guessFrameId_.empty()) return rtabmap::Transform();
  std::string error;
  *guessPose = rtabmap_conversions::lookupTransform(*tfBuffer_, guessFrameId_, frameId_, stamp, waitForTransform_,
                                                    &error);
  if (guessPose->isNull()) {
    if (errors_.due("guess pose")) NODELET_WARN("%s: no motion guess: %s", getName().c_str(), error.c_str());
    return rtabmap::Transform();
  }
  if (previousStamp_.isZero()) return rtabmap::Transform();
  const rtabmap::Transform motion = rtabmap_conversions::lookupMotion(*tfBuffer_, guessFrameId_, frameId_,
                                                                      previousStamp_, stamp, waitForTransform_, &error);
  if (motion.isNull() && errors_.due("guess motion")) {
    NODELET_WARN("%s: no motion guess: %s", getName().c_str(), error.c_str());
  }
  return motion;
}

void OdometryNodelet::onImu(const sensor_msgs::ImuConstPtr& msg) {
  std::string why;
  rtabmap::IMU imu;
  if (imuOrientations_.add(*msg, &why, &imu) == rtabmap_conversions::ImuOrientationBuffer::Intake::kRefused) {
    if (imuWarnings_.due("imu")) NODELET_WARN("%s: imu message ignored: %s.", getName().c_str(), why.c_str());
    return;
  }
  // Its angular velocity too, for the guess when the frames have no orientation: handed to the
  // odometry by the next frame (this callback does not wait for an update to end).
  if (imu.angularVelocity.isZero(0.0)) return;
  std::lock_guard<std::mutex> lock(gyroMutex_);
  if (pendingGyro_.size() >= kMaxPendingGyro) {  // no frame for seconds (paused): the newest matter
    pendingGyro_.erase(pendingGyro_.begin(), pendingGyro_.begin() + kMaxPendingGyro / 2);
  }
  pendingGyro_.push_back({msg->header.stamp, msg->header.frame_id, imu});
}

void OdometryNodelet::handOverGyroSamples() {
  std::vector<PendingGyro> samples;
  {
    std::lock_guard<std::mutex> lock(gyroMutex_);
    samples.swap(pendingGyro_);
  }
  for (PendingGyro& g : samples) {
    std::string why;
    g.imu.localTransform = imuOrientations_.mountOf(
        g.frameId, [&](const std::string& frameId, std::string* e) { return sensorPose(frameId, g.stamp, e); }, &why);
    if (g.imu.localTransform.isNull()) {
      if (errors_.due("imu mount")) NODELET_WARN("%s: imu sample not used: %s.", getName().c_str(), why.c_str());
      continue;
    }
    odometry_->addImu(g.stamp.toSec(), g.imu);
  }
}

bool OdometryNodelet::attachImuOrientation(rtabmap::SensorData& frame, const ros::Time& stamp) {
  const bool waiting = waitImuToInit_ && odometry_->framesProcessed() == 0;
  if (imuOrientations_.empty() && !waiting) return true;
  std::string why = "no message on the imu topic yet";
  const std::optional<rtabmap::IMU> imu =
      imuOrientations_.empty()
          ? std::nullopt
          : imuOrientations_.imuAt(
                stamp.toSec(), [&](const std::string& frameId, std::string* e) { return sensorPose(frameId, stamp, e); },
                &why);
  if (imu) {
    frame.setIMU(*imu);
    return true;
  }
  if (errors_.due(waiting ? "imu wait" : "imu attach")) {
    NODELET_WARN("%s: frame at %.6f has no imu orientation: %s%s.", getName().c_str(), stamp.toSec(), why.c_str(),
                 waiting ? "; dropped until one comes (wait_imu_to_init)" : "");
  }
  return !waiting;
}

void OdometryNodelet::onData(const rtabmap_sync::SyncedData& d) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (paused_ || !odometry_) return;
  if (d.clockJumps != clockJumpsSeen_) {
    // ROS time went back: a bag played again or a simulator reset. Its sensors start over where
    // they started, so odometry does too (and rtabmap starts a new map).
    clockJumpsSeen_ = d.clockJumps;
    NODELET_WARN("%s: ROS time jumped back; odometry restarts at the origin.", getName().c_str());
    resetLocked(rtabmap::Transform::Identity());
    imuOrientations_.clear();
    std::lock_guard<std::mutex> gyroLock(gyroMutex_);
    pendingGyro_.clear();
  }
  const ros::Time stamp = d.stamp;
  if (!limiter_.accept(stamp.toSec())) return;
  handOverGyroSamples();  // before makeFrame: deskewing may turn a sweep as the gyroscope did
  std::string error;
  std::optional<rtabmap::SensorData> frame = makeFrame(d, &error);
  if (!frame) {
    if (errors_.due(rtabmap_odom::throttleKey(error))) {
      NODELET_ERROR("%s: %s; frame at %.6f dropped.", getName().c_str(), error.c_str(), stamp.toSec());
    }
    return;
  }
  frame->setStamp(stamp.toSec());
  if (!attachImuOrientation(*frame, stamp)) return;
  rtabmap::Transform guessPose;
  const rtabmap::Transform guess = guessMotion(stamp, &guessPose);
  rtabmap::OdometryInfo info;
  const rtabmap::Transform pose = guess.isNull() ? odometry_->process(*frame, &info)
                                                 : odometry_->process(*frame, guess, &info);
  previousStamp_ = stamp;
  if (!pose.isNull() && !info.transform.isNull() && info.interval > 0.0) {
    lastMotion_ = info.transform;
    lastInterval_ = info.interval;
  } else if (info.autoReset) {
    lastMotion_ = rtabmap::Transform();
  }  // a lost frame keeps the last velocity: the robot most likely still moves the same way
  ++updatesSinceWatch_;
  if (pose.isNull()) reportLost(info, stamp);
  publish(*frame, pose, info, stamp, guessPose);
}

void OdometryNodelet::reportLost(const rtabmap::OdometryInfo& info, const ros::Time& stamp) {
  // One line per distinct reason (a stream of identical lost frames would flood the log).
  if (errors_.due("lost " + rtabmap_odom::throttleKey(info.lostReason))) {
    NODELET_WARN("%s: odometry lost at %.6f (%d consecutive frames): %s%s", getName().c_str(), stamp.toSec(),
                 odometry_->lostCount(), info.lostReason.c_str(),
                 info.autoReset ? " (Odom/ResetCountdown reached: odometry reset)" : "");
  }
}

void OdometryNodelet::publish(const rtabmap::SensorData& frame, const rtabmap::Transform& pose,
                              const rtabmap::OdometryInfo& info, const ros::Time& stamp,
                              const rtabmap::Transform& guessPose) {
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = odomFrameId_;
  if (!pose.isNull() && publishTf_) publishTf(pose, guessPose, header);
  if (!pose.isNull() || publishNullWhenLost_) odomPub_.publish(odomMessage(pose, info, header));
  if (odomInfoPub_.getNumSubscribers() > 0) {
    odomInfoPub_.publish(rtabmap_conversions::odomInfoToMsg(info, odometry_->type(), header));
  }
  if (!pose.isNull()) publishClouds(frame, pose, header);
}

void OdometryNodelet::publishTf(const rtabmap::Transform& pose, const rtabmap::Transform& guessPose,
                                const std_msgs::Header& header) {
  geometry_msgs::TransformStamped t;
  t.header = header;
  if (guessFrameId_.empty()) {
    t.child_frame_id = frameId_;
    t.transform = tf2::eigenToTransform(pose.toEigen()).transform;
  } else if (!guessPose.isNull()) {
    // frame_id already has a parent (the guess frame): publish odom -> guess frame instead.
    t.child_frame_id = guessFrameId_;
    t.transform = tf2::eigenToTransform(rtabmap_odom::guessFrameCorrection(pose, guessPose).toEigen()).transform;
  } else {
    return;  // without the guess frame's pose, no correction can be computed
  }
  tfBroadcaster_->sendTransform(t);
}

nav_msgs::Odometry OdometryNodelet::odomMessage(const rtabmap::Transform& pose, const rtabmap::OdometryInfo& info,
                                                const std_msgs::Header& header) const {
  // Lost: a null pose, which odometryToMsg writes with 9999 variances.
  nav_msgs::Odometry msg = rtabmap_conversions::odometryToMsg(pose, info.covariance, header, frameId_);
  if (pose.isNull()) return msg;
  const Eigen::Matrix<double, 6, 1> v = rtabmap_odom::twistFromMotion(info.transform, info.interval);
  msg.twist.twist.linear.x = v[0];
  msg.twist.twist.linear.y = v[1];
  msg.twist.twist.linear.z = v[2];
  msg.twist.twist.angular.x = v[3];
  msg.twist.twist.angular.y = v[4];
  msg.twist.twist.angular.z = v[5];
  // The classic convention: the twist has the covariance of the motion it comes from.
  msg.twist.covariance = msg.pose.covariance;
  return msg;
}

void OdometryNodelet::publishClouds(const rtabmap::SensorData& frame, const rtabmap::Transform& pose,
                                    const std_msgs::Header& header) {
  if (lastFramePub_.getNumSubscribers() > 0) {
    const rtabmap::LaserScan cloud = rtabmap_odom::scanInFrame(frameCloud(frame), pose);
    if (!cloud.empty()) lastFramePub_.publish(rtabmap_conversions::laserScanToCloudMsg(cloud, header));
  }
  if (localMapPub_.getNumSubscribers() == 0) return;
  rtabmap::LaserScan map;
  if (auto* f2m = dynamic_cast<const rtabmap::OdometryF2M*>(odometry_.get())) {
    map = rtabmap_odom::pointsAsScan(f2m->localMapPoints());
  } else if (auto* s2m = dynamic_cast<const rtabmap::OdometryS2M*>(odometry_.get())) {
    map = s2m->localMap();
  }
  if (!map.empty()) localMapPub_.publish(rtabmap_conversions::laserScanToCloudMsg(map, header));
}

void OdometryNodelet::resetTo(const rtabmap::Transform& pose) {
  std::lock_guard<std::mutex> lock(mutex_);
  resetLocked(pose);
}

void OdometryNodelet::resetLocked(const rtabmap::Transform& pose) {
  odometry_->reset(pose);
  previousStamp_ = ros::Time();
  lastMotion_ = rtabmap::Transform();
  limiter_.reset();
  NODELET_INFO("%s: odometry reset to %s", getName().c_str(), pose.prettyPrint().c_str());
}

bool OdometryNodelet::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  resetTo(rtabmap::Transform::Identity());
  return true;
}

bool OdometryNodelet::onResetToPose(rtabmap_ros::ResetPose::Request& req, rtabmap_ros::ResetPose::Response&) {
  for (float v : {req.x, req.y, req.z, req.roll, req.pitch, req.yaw}) {
    if (!std::isfinite(v)) {
      NODELET_ERROR("%s: reset_odom_to_pose: the pose is not finite; odometry not reset.", getName().c_str());
      return false;
    }
  }
  resetTo(rtabmap::Transform(req.x, req.y, req.z, req.roll, req.pitch, req.yaw));
  return true;
}

bool OdometryNodelet::onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (paused_) NODELET_WARN("%s: odometry is already paused.", getName().c_str());
  else NODELET_INFO("%s: odometry paused.", getName().c_str());
  paused_ = true;
  return true;
}

bool OdometryNodelet::onResume(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!paused_) NODELET_WARN("%s: odometry was not paused.", getName().c_str());
  else NODELET_INFO("%s: odometry resumed.", getName().c_str());
  paused_ = false;
  // The guess must not span the pause: the robot may have moved a lot meanwhile.
  previousStamp_ = ros::Time();
  lastMotion_ = rtabmap::Transform();
  return true;
}

void OdometryNodelet::onRateWatch(const ros::WallTimerEvent&) {
  const ros::WallTime now = ros::WallTime::now();
  int updates;
  bool paused;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    updates = updatesSinceWatch_;
    updatesSinceWatch_ = 0;
    paused = paused_;
  }
  const double window = (now - lastWatch_).toSec();
  lastWatch_ = now;
  // No update at all is the synchroniser's 5-second warning; this one is about falling behind.
  if (!paused && updates > 0 && rtabmap_odom::updateRateTooLow(updates, window, expectedUpdateRate_)) {
    NODELET_WARN("%s: odometry updated at %.1f Hz over the last %.0f s, below expected_update_rate %.1f Hz.",
                 getName().c_str(), updates / window, window, expectedUpdateRate_);
  }
}

}  // namespace rtabmap_ros

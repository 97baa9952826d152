// rtabmap nodelet: what a synchronised set becomes for the core: the odometry pose of the
// robot (odom topic or tf) with the covariance of the motion, and the frame (camera images
// and/or laser scan placed on the robot through tf). Interface: RtabmapNodelet.h.
#include "RtabmapNodelet.h"

#include <algorithm>

#include "rtabmap_conversions/LandmarkConversions.h"
#include "rtabmap_conversions/OdometryConversions.h"
#include "rtabmap_conversions/RGBDImageConversions.h"
#include "rtabmap_conversions/TfLookup.h"
#include "rtabmap_slam_node/OdomSensorSync.h"
#include "rtabmap_odom/PrivateParameters.h"
#include "rtabmap_sync/FrameAssembly.h"

namespace rtabmap_ros {

rtabmap::Transform RtabmapNodelet::sensorPose(const std::string& sensorFrame, const ros::Time& stamp,
                                              std::string* error) const {
  if (sensorFrame.empty()) {
    if (error) *error = "the message has no frame_id";
    return rtabmap::Transform();
  }
  return rtabmap_conversions::lookupTransform(*tfBuffer_, frameId_, sensorFrame, stamp, waitForTransform_, error);
}

rtabmap::Transform RtabmapNodelet::syncedSensorPose(const rtabmap_sync::SyncedData& d, const std::string& sensorFrame,
                                                    const ros::Time& stamp, std::string* error) const {
  const rtabmap::Transform local = sensorPose(sensorFrame, stamp, error);
  if (!odomSensorSync_) return local;
  // The odometry pose given to the core is the odom message's, or tf's at the data's stamp.
  const ros::Time odomStamp = d.odom ? d.odom->header.stamp : d.stamp;
  return rtabmap_slam_node::odomSyncedLocalTransform(*tfBuffer_, odomFrameId_, frameId_, local, odomStamp, stamp,
                                                     waitForTransform_, error);
}

bool RtabmapNodelet::odometryOf(const rtabmap_sync::SyncedData& d, rtabmap::Transform* pose,
                                rtabmap_slam_node::Covariance6* cov, std::string* error) {
  if (!d.odom) {
    *pose = rtabmap_conversions::lookupTransform(*tfBuffer_, odomFrameId_, frameId_, d.stamp, waitForTransform_, error);
    *cov = rtabmap_slam_node::tfOdometryCovariance(odomTfLinearVariance_, odomTfAngularVariance_);
    return !pose->isNull();
  }
  std::string why;
  std::optional<rtabmap_conversions::OdometryReading> r = rtabmap_conversions::odometryFromMsg(*d.odom, &why);
  if (!r) {
    *error = "odom: " + why;
    return false;
  }
  if (r->lost()) {
    *error = "odom: odometry is lost (null pose or 9999 covariance)";
    previousOdomCovariance_.reset();
    return false;
  }
  if (!r->childFrameId.empty() && r->childFrameId != frameId_) {
    // The odometry is of another frame than the robot's base: bring it to frame_id.
    const rtabmap::Transform local = sensorPose(r->childFrameId, d.odom->header.stamp, error);
    if (local.isNull()) return false;
    r->pose = r->pose * local;
  }
  *pose = r->pose;
  *cov = rtabmap_slam_node::motionCovariance(r->covariance, previousOdomCovariance_ ? &*previousOdomCovariance_ : nullptr,
                                             odomCovarianceCumulative_);
  previousOdomCovariance_ = r->covariance;
  return true;
}

std::optional<rtabmap::LaserScan> RtabmapNodelet::makeScan(const rtabmap_sync::SyncedData& d,
                                                           std::string* error) const {
  const std_msgs::Header& header = d.scan ? d.scan->header : d.scanCloud->header;
  const rtabmap::Transform local = syncedSensorPose(d, header.frame_id, header.stamp, error);
  if (local.isNull()) return std::nullopt;
  return rtabmap_sync::syncedScan(d.scan, d.scanCloud, local, error);
}

std::optional<rtabmap::SensorData> RtabmapNodelet::makeFrame(const rtabmap_sync::SyncedData& d,
                                                             std::string* error) const {
  std::optional<rtabmap::SensorData> frame;
  if (d.rgb && d.depth && d.rgbCameraInfo) {
    frame = rtabmap_sync::rgbdFrame(*d.rgb, *d.depth, *d.rgbCameraInfo, {}, error);
    if (!frame) return std::nullopt;
    const rtabmap::Transform local = syncedSensorPose(d, d.rgb->header.frame_id, d.rgb->header.stamp, error);
    if (local.isNull()) return std::nullopt;
    std::vector<rtabmap::CameraModel> models = frame->cameraModels();
    for (rtabmap::CameraModel& m : models) m.setLocalTransform(local);
    frame->setRGBDImage(frame->imageRaw(), frame->depthOrRightRaw(), models);
  } else if (d.left && d.right && d.leftCameraInfo && d.rightCameraInfo) {
    frame = rtabmap_sync::stereoFrame(*d.left, *d.right, *d.leftCameraInfo, *d.rightCameraInfo, error);
    if (!frame) return std::nullopt;
    const rtabmap::Transform local = syncedSensorPose(d, d.left->header.frame_id, d.left->header.stamp, error);
    if (local.isNull()) return std::nullopt;
    std::vector<rtabmap::StereoCameraModel> models = frame->stereoCameraModels();
    for (rtabmap::StereoCameraModel& m : models) m.setLocalTransform(local);
    frame->setStereoImage(frame->imageRaw(), frame->depthOrRightRaw(), models);
  } else if (d.rgb) {
    *error = "a monocular camera (subscribe_rgb) is not supported by the SLAM node: it needs depth or stereo";
    return std::nullopt;
  } else if (d.rgbdImages.size() == 1) {
    const rtabmap_ros::RGBDImage& msg = *d.rgbdImages.front();
    const rtabmap::Transform local = syncedSensorPose(d, msg.header.frame_id, msg.header.stamp, error);
    if (local.isNull()) return std::nullopt;
    std::string why;
    frame = rtabmap_conversions::rgbdImageFromMsg(msg, local, &why);
    if (!frame) {
      *error = "rgbd_image: " + why;
      return std::nullopt;
    }
  } else if (!d.rgbdImages.empty() || d.rgbdImagesMsg) {
    // Several cameras side by side (rgbd_cameras N > 1 or 0; all RGB-D or all stereo), each
    // placed by tf at its frame.
    const auto poseOf = [&](const std::string& frameId, const ros::Time& stamp, std::string* why) {
      return syncedSensorPose(d, frameId, stamp, why);
    };
    frame = rtabmap_sync::rgbdCamerasFrame(d.rgbdImagesMsg, d.rgbdImages, poseOf, error);
    if (!frame) return std::nullopt;
  } else {
    frame = rtabmap::SensorData();
  }
  if (d.scan || d.scanCloud) {
    std::optional<rtabmap::LaserScan> scan = makeScan(d, error);
    if (!scan) return std::nullopt;
    frame->setLaserScan(*scan);
  }
  frame->setStamp(d.stamp.toSec());
  return frame;
}

void RtabmapNodelet::onImu(const sensor_msgs::ImuConstPtr& msg) {
  std::string why;
  // A raw IMU has nothing to say about gravity here: silently unused, as it may serve others.
  if (imuOrientations_.add(*msg, &why) == rtabmap_conversions::ImuOrientationBuffer::Intake::kRefused &&
      imuWarnings_.due("imu")) {
    NODELET_WARN("%s: imu message ignored: %s.", getName().c_str(), why.c_str());
  }
}

void RtabmapNodelet::attachImuOrientation(rtabmap::SensorData& frame, const ros::Time& stamp) {
  if (imuOrientations_.empty()) return;
  std::string why;
  const std::optional<rtabmap::IMU> imu = imuOrientations_.imuAt(
      stamp.toSec(), [&](const std::string& frameId, std::string* e) { return sensorPose(frameId, stamp, e); }, &why);
  if (imu) {
    frame.setIMU(*imu);
  } else if (warnings_.due("imu attach")) {
    NODELET_WARN("%s: frame at %.6f has no gravity reference: %s.", getName().c_str(), stamp.toSec(), why.c_str());
  }
}

void RtabmapNodelet::onLandmarkDetection(const rtabmap_ros::LandmarkDetectionConstPtr& msg) {
  addLandmarkDetection(*msg);
}

void RtabmapNodelet::onLandmarkDetections(const rtabmap_ros::LandmarkDetectionsConstPtr& msg) {
  for (const rtabmap_ros::LandmarkDetection& d : msg->landmarks) addLandmarkDetection(d);
}

void RtabmapNodelet::addLandmarkDetection(const rtabmap_ros::LandmarkDetection& msg) {
  std::string why;
  // Without mutex_ (parameters_ may change meanwhile): a detection without covariance gets the
  // node's Marker/Variance* when a frame takes it.
  const std::optional<rtabmap::Landmark> l = rtabmap_conversions::landmarkFromMsg(msg, 1.0, 1.0, &why);
  if (!l) {
    std::lock_guard<std::mutex> lock(landmarkWarningsMutex_);
    if (landmarkWarnings_.due(rtabmap_odom::throttleKey(why))) {
      NODELET_WARN("%s: landmark detection ignored: %s.", getName().c_str(), why.c_str());
    }
    return;
  }
  const bool noCovariance = std::all_of(msg.pose.covariance.begin(), msg.pose.covariance.end(),
                                        [](double v) { return v == 0.0; });
  landmarkDetections_.add({msg.header.stamp.toSec(), msg.header.frame_id, *l, noCovariance});
}

void RtabmapNodelet::attachLandmarks(rtabmap::SensorData& frame, const ros::Time& stamp) {
  if (landmarkDetections_.size() == 0) return;
  const auto poseOf = [&](const std::string& frameId, double detected, std::string* why) {
    // The camera on the robot when it saw the landmark, moved by the odometry to the frame's stamp.
    const ros::Time at(detected);
    const rtabmap::Transform local = sensorPose(frameId, at, why);
    if (local.isNull()) return local;
    return rtabmap_slam_node::odomSyncedLocalTransform(*tfBuffer_, odomFrameId_, frameId_, local, stamp, at,
                                                       waitForTransform_, why);
  };
  Eigen::Matrix<double, 6, 6> markers = Eigen::Matrix<double, 6, 6>::Zero();
  const double linear = rtabmap::Parameters::getFloat(parameters_, rtabmap::Parameters::kMarkerVarianceLinear());
  const double angular = rtabmap::Parameters::getFloat(parameters_, rtabmap::Parameters::kMarkerVarianceAngular());
  markers.diagonal() << linear, linear, linear, angular, angular, angular;
  std::vector<std::string> problems;
  const rtabmap::Landmarks seen = landmarkDetections_.take(stamp.toSec(), poseOf, markers, &problems);
  for (const std::string& p : problems) {
    if (warnings_.due(rtabmap_odom::throttleKey(p))) NODELET_WARN("%s: %s.", getName().c_str(), p.c_str());
  }
  if (!seen.empty()) frame.setLandmarks(seen);
}

void RtabmapNodelet::onInitialPose(const geometry_msgs::PoseWithCovarianceStampedConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!haveCore("initialpose")) return;
  geometry_msgs::PoseStamped stamped;
  stamped.header = msg->header;
  stamped.pose = msg->pose.pose;
  std::string error;
  const rtabmap::Transform pose = poseInMap(stamped, &error);  // goals and initial poses alike
  if (pose.isNull()) {
    NODELET_WARN("%s: initialpose ignored: %s.", getName().c_str(), error.c_str());
    return;
  }
  applyInitialPose(pose, "initialpose");
}

bool RtabmapNodelet::applyInitialPose(const rtabmap::Transform& pose, const char* from) {
  std::string why;
  if (!core_->setInitialPose(pose, &why)) {
    NODELET_WARN("%s: %s %s refused: %s", getName().c_str(), from, pose.prettyPrint().c_str(), why.c_str());
    return false;
  }
  {
    // Moved at once when odometry was already received (else at the next update).
    std::lock_guard<std::mutex> tfLock(tfMutex_);
    mapToOdom_ = core_->mapCorrection();
  }
  NODELET_INFO("%s: %s: the robot is at %s in %s (%s).", getName().c_str(), from, pose.prettyPrint().c_str(),
               mapFrameId_.c_str(), mapping_ ? "the new map starts there" : "localization starts from there");
  return true;
}

}  // namespace rtabmap_ros

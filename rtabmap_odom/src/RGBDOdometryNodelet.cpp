// rgbd_odometry: visual odometry (F2M or F2F, Odom/Strategy) from an RGB-D camera:
// rgb/image + depth/image + rgb/camera_info (default), or rgbd_image (subscribe_rgbd, e.g. from
// rgbd_sync), or several cameras (rgbd_cameras N: rgbd_image0..N-1; 0: rgbd_images).
// Common parameters, topics and services: OdometryNodelet.h.
#include <pluginlib/class_list_macros.hpp>

#include "OdometryNodelet.h"
#include "rtabmap_conversions/RGBDImageConversions.h"
#include "rtabmap_odom/OdometryOutputs.h"
#include "rtabmap_sync/FrameAssembly.h"

namespace rtabmap_ros {

class RGBDOdometryNodelet : public OdometryNodelet {
 public:
  RGBDOdometryNodelet() : OdometryNodelet(false) {}

 private:
  rtabmap_sync::SubscribeOptions defaultSubscribeOptions() const override {
    rtabmap_sync::SubscribeOptions o;
    o.subscribeDepth = !rgbd_;  // subscribe_rgbd alone means rgbd_image, without a conflict
    return o;
  }

  void readParameters(ros::NodeHandle& pnh, rtabmap::ParametersMap&) override {
    pnh.param("subscribe_rgbd", rgbd_, rgbd_);
  }

  std::optional<rtabmap::SensorData> makeFrame(const rtabmap_sync::SyncedData& d, std::string* error) override {
    if (d.rgb) return fromTopics(d, error);
    if (!d.rgbdImagesMsg && d.rgbdImages.size() == 1) {
      const rtabmap_ros::RGBDImage& msg = *d.rgbdImages.front();
      const rtabmap::Transform local = sensorPose(msg.header.frame_id, msg.header.stamp, error);
      if (local.isNull()) return std::nullopt;
      std::string why;
      auto frame = rtabmap_conversions::rgbdImageFromMsg(msg, local, &why);
      if (!frame && error) *error = "rgbd_image: " + why;
      return frame;
    }
    // Several cameras side by side (rgbd_cameras N > 1 or 0), each placed by tf at its frame.
    const auto poseOf = [this](const std::string& frameId, const ros::Time& stamp, std::string* why) {
      return sensorPose(frameId, stamp, why);
    };
    return rtabmap_sync::rgbdCamerasFrame(d.rgbdImagesMsg, d.rgbdImages, poseOf, error);
  }

  // rgb/image + depth/image + rgb/camera_info, placed on the robot through tf.
  std::optional<rtabmap::SensorData> fromTopics(const rtabmap_sync::SyncedData& d, std::string* error) {
    std::optional<rtabmap::SensorData> frame = rtabmap_sync::rgbdFrame(*d.rgb, *d.depth, *d.rgbCameraInfo, {}, error);
    if (!frame) return std::nullopt;
    const rtabmap::Transform local = sensorPose(d.rgb->header.frame_id, d.rgb->header.stamp, error);
    if (local.isNull()) return std::nullopt;
    std::vector<rtabmap::CameraModel> models = frame->cameraModels();
    for (rtabmap::CameraModel& m : models) m.setLocalTransform(local);
    frame->setRGBDImage(frame->imageRaw(), frame->depthOrRightRaw(), models);
    return frame;
  }

  rtabmap::LaserScan frameCloud(const rtabmap::SensorData& frame) const override {
    return rtabmap_odom::pointsAsScan(frame.keypoints3D());  // the frame's features, base frame
  }

  bool rgbd_ = false;  // subscribe_rgbd
};

}  // namespace rtabmap_ros

PLUGINLIB_EXPORT_CLASS(rtabmap_ros::RGBDOdometryNodelet, nodelet::Nodelet)

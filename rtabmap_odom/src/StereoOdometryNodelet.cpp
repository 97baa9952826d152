// stereo_odometry: visual odometry (F2M or F2F, Odom/Strategy) from a rectified stereo camera:
// left/image_rect + right/image_rect + left/camera_info + right/camera_info (default), or a
// stereo rgbd_image (subscribe_rgbd, e.g. from stereo_sync).
// Common parameters, topics and services: OdometryNodelet.h.
#include <pluginlib/class_list_macros.hpp>

#include "OdometryNodelet.h"
#include "rtabmap_conversions/RGBDImageConversions.h"
#include "rtabmap_odom/OdometryOutputs.h"
#include "rtabmap_sync/FrameAssembly.h"

namespace rtabmap_ros {

class StereoOdometryNodelet : public OdometryNodelet {
 public:
  StereoOdometryNodelet() : OdometryNodelet(false) {}

 private:
  rtabmap_sync::SubscribeOptions defaultSubscribeOptions() const override {
    rtabmap_sync::SubscribeOptions o;
    o.subscribeStereo = !rgbd_;  // subscribe_rgbd alone means rgbd_image, without a conflict
    return o;
  }

  void readParameters(ros::NodeHandle& pnh, rtabmap::ParametersMap&) override {
    pnh.param("subscribe_rgbd", rgbd_, rgbd_);
  }

  std::optional<rtabmap::SensorData> makeFrame(const rtabmap_sync::SyncedData& d, std::string* error) override {
    if (!d.left) return fromRgbdImage(d, error);
    std::optional<rtabmap::SensorData> frame =
        rtabmap_sync::stereoFrame(*d.left, *d.right, *d.leftCameraInfo, *d.rightCameraInfo, error);
    if (!frame) return std::nullopt;
    const rtabmap::Transform local = sensorPose(d.left->header.frame_id, d.left->header.stamp, error);
    if (local.isNull()) return std::nullopt;
    rtabmap::StereoCameraModel model = frame->stereoCameraModels().front();
    model.setLocalTransform(local);
    frame->setStereoImage(frame->imageRaw(), frame->depthOrRightRaw(), model);
    return frame;
  }

  std::optional<rtabmap::SensorData> fromRgbdImage(const rtabmap_sync::SyncedData& d, std::string* error) {
    if (d.rgbdImages.size() != 1) {
      if (error) *error = "stereo_odometry takes one stereo camera (rgbd_cameras 1)";
      return std::nullopt;
    }
    const rtabmap_ros::RGBDImage& msg = *d.rgbdImages.front();
    const rtabmap::Transform local = sensorPose(msg.header.frame_id, msg.header.stamp, error);
    if (local.isNull()) return std::nullopt;
    std::string why;
    std::optional<rtabmap::SensorData> frame = rtabmap_conversions::rgbdImageFromMsg(msg, local, &why);
    if (!frame) {
      if (error) *error = "rgbd_image: " + why;
    } else if (!frame->isStereo()) {
      if (error) *error = "rgbd_image is not a stereo pair (its right camera_info needs Tx < 0); use rgbd_odometry";
      return std::nullopt;
    }
    return frame;
  }

  rtabmap::LaserScan frameCloud(const rtabmap::SensorData& frame) const override {
    return rtabmap_odom::pointsAsScan(frame.keypoints3D());
  }

  bool rgbd_ = false;  // subscribe_rgbd
};

}  // namespace rtabmap_ros

PLUGINLIB_EXPORT_CLASS(rtabmap_ros::StereoOdometryNodelet, nodelet::Nodelet)

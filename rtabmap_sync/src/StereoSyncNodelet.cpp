// stereo_sync: synchronises left/image_rect, right/image_rect, left/camera_info and
// right/camera_info (a rectified pair) into one rtabmap_ros/RGBDImage on `rgbd_image` (rgb =
// left, depth = right as grey, right camera_info with Tx = -fx * baseline), and
// `rgbd_image/compressed`.
//
// Parameters (classic rtabmap_ros names):
//   approx_sync (bool, false)            stereo cameras are triggered together: exact by default
//   approx_sync_max_interval (double, 0) max stamp spread in a set, seconds (0 = unlimited)
//   queue_size (int, 10)                 synchroniser and subscriber queues
//   compressed_rate (double, 0)          max rate of rgbd_image/compressed, Hz (0 = every set)
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>

#include "RGBDPublisher.h"
#include "rtabmap_sync/DataSubscriber.h"
#include "rtabmap_sync/FrameAssembly.h"
#include "rtabmap_sync/LogThrottle.h"

namespace rtabmap_ros {

class StereoSyncNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    rtabmap_sync::SubscribeOptions options;
    options.subscribeStereo = true;
    pnh.param("approx_sync", options.approxSync, false);
    pnh.param("approx_sync_max_interval", options.approxSyncMaxInterval, 0.0);
    pnh.param("queue_size", options.queueSize, 10);
    pnh.param("image_transport", options.imageTransport, options.imageTransport);
    double compressedRate = 0.0;
    pnh.param("compressed_rate", compressedRate, compressedRate);
    publisher_.advertise(nh, compressedRate);
    std::string error;
    if (!subscriber_.setup(nh, getName(), options, [this](const rtabmap_sync::SyncedData& d) { onData(d); },
                           &error)) {
      NODELET_FATAL("%s", error.c_str());
    }
  }

  void onData(const rtabmap_sync::SyncedData& d) {
    if (!publisher_.wanted()) return;
    std::string error;
    std::optional<rtabmap::SensorData> frame =
        rtabmap_sync::stereoFrame(*d.left, *d.right, *d.leftCameraInfo, *d.rightCameraInfo, &error);
    if (!frame) {
      if (errors_.due(error)) NODELET_ERROR("stereo_sync: %s; frame at %.6f dropped.", error.c_str(), d.stamp.toSec());
      return;
    }
    try {
      publisher_.publish(*frame, d.left->header, d.rightCameraInfo->header.frame_id);
    } catch (const rtabmap::Error& e) {
      if (errors_.due(e.what())) NODELET_ERROR("stereo_sync: cannot encode the frame (%s); dropped.", e.what());
    }
  }

  rtabmap_sync::LogThrottle errors_;
  rtabmap_sync::RGBDPublisher publisher_;
  rtabmap_sync::DataSubscriber subscriber_;
};

}  // namespace rtabmap_ros

PLUGINLIB_EXPORT_CLASS(rtabmap_ros::StereoSyncNodelet, nodelet::Nodelet)

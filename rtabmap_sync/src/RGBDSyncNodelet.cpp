// rgbd_sync: synchronises rgb/image, depth/image and rgb/camera_info into one
// rtabmap_ros/RGBDImage on `rgbd_image` (and `rgbd_image/compressed`), so downstream nodes
// subscribe to a single topic and never see an RGB frame paired with the wrong depth frame.
//
// Parameters (classic rtabmap_ros names):
//   approx_sync (bool, true)             ApproximateTime instead of ExactTime policy
//   approx_sync_max_interval (double, 0) max stamp spread in a set, seconds (0 = unlimited)
//   queue_size (int, 10)                 synchroniser and subscriber queues
//   depth_scale (double, 1.0)            multiply depth values (fix a miscalibrated sensor)
//   decimation (int, 1)                  keep one pixel in N per axis (images and camera info)
//   compressed_rate (double, 0)          max rate of rgbd_image/compressed, Hz (0 = every set)
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>

#include "RGBDPublisher.h"
#include "rtabmap_sync/DataSubscriber.h"
#include "rtabmap_sync/FrameAssembly.h"
#include "rtabmap_sync/LogThrottle.h"

namespace rtabmap_ros {

class RGBDSyncNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    rtabmap_sync::SubscribeOptions options;
    options.subscribeDepth = true;
    pnh.param("approx_sync", options.approxSync, true);
    pnh.param("approx_sync_max_interval", options.approxSyncMaxInterval, 0.0);
    pnh.param("queue_size", options.queueSize, 10);
    pnh.param("image_transport", options.imageTransport, options.imageTransport);
    pnh.param("depth_image_transport", options.depthImageTransport, options.depthImageTransport);
    pnh.param("depth_scale", frameOptions_.depthScale, 1.0);
    pnh.param("decimation", frameOptions_.decimation, 1);
    double compressedRate = 0.0;
    pnh.param("compressed_rate", compressedRate, compressedRate);
    if (frameOptions_.decimation < 1) {
      NODELET_ERROR("rgbd_sync: decimation must be >= 1 (got %d), using 1.", frameOptions_.decimation);
      frameOptions_.decimation = 1;
    }
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
    std::optional<rtabmap::SensorData> frame = rtabmap_sync::rgbdFrame(*d.rgb, *d.depth, *d.rgbCameraInfo,
                                                                      frameOptions_, &error);
    if (!frame) {
      if (errors_.due(error)) NODELET_ERROR("rgbd_sync: %s; frame at %.6f dropped.", error.c_str(), d.stamp.toSec());
      return;
    }
    try {
      // The set's stamp and frame are the RGB camera's: features and poses come from it.
      publisher_.publish(*frame, d.rgb->header);
    } catch (const rtabmap::Error& e) {
      if (errors_.due(e.what())) NODELET_ERROR("rgbd_sync: cannot encode the frame (%s); dropped.", e.what());
    }
  }

  rtabmap_sync::RgbdFrameOptions frameOptions_;
  rtabmap_sync::LogThrottle errors_;
  rtabmap_sync::RGBDPublisher publisher_;
  rtabmap_sync::DataSubscriber subscriber_;
};

}  // namespace rtabmap_ros

PLUGINLIB_EXPORT_CLASS(rtabmap_ros::RGBDSyncNodelet, nodelet::Nodelet)

// rgbdx_sync: synchronises several RGB-D cameras, rgbd_image0 .. rgbd_image<N-1> (each an
// rtabmap_ros/RGBDImage, e.g. from rgbd_sync), into one rtabmap_ros/RGBDImages on
// `rgbd_images`, stamped with camera 0's stamp. The images pass through untouched.
//
// Parameters (classic rtabmap_ros names):
//   rgbd_cameras (int, 2)                number of cameras (2 .. 9)
//   approx_sync (bool, true)             ApproximateTime instead of ExactTime policy
//   approx_sync_max_interval (double, 0) max stamp spread in a set, seconds (0 = unlimited)
//   queue_size (int, 10)                 synchroniser and subscriber queues
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <rtabmap_ros/RGBDImages.h>

#include "rtabmap_sync/DataSubscriber.h"
#include "rtabmap_sync/FrameAssembly.h"
#include "rtabmap_sync/LogThrottle.h"

namespace rtabmap_ros {

class RGBDXSyncNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    rtabmap_sync::SubscribeOptions options;
    options.subscribeRgbd = true;
    pnh.param("rgbd_cameras", options.rgbdCameras, 2);
    pnh.param("approx_sync", options.approxSync, true);
    pnh.param("approx_sync_max_interval", options.approxSyncMaxInterval, 0.0);
    pnh.param("queue_size", options.queueSize, 10);
    if (options.rgbdCameras < 2) {
      // One camera needs no sync, and 0 would mean "rgbd_images" as input.
      NODELET_ERROR("rgbdx_sync: rgbd_cameras must be >= 2 (got %d), using 2.", options.rgbdCameras);
      options.rgbdCameras = 2;
    }
    publisher_ = nh.advertise<rtabmap_ros::RGBDImages>("rgbd_images", 1);
    std::string error;
    if (!subscriber_.setup(nh, getName(), options, [this](const rtabmap_sync::SyncedData& d) { onData(d); },
                           &error)) {
      NODELET_FATAL("%s", error.c_str());
    }
  }

  void onData(const rtabmap_sync::SyncedData& d) {
    if (publisher_.getNumSubscribers() == 0) return;
    auto out = boost::make_shared<rtabmap_ros::RGBDImages>();
    out->header = d.rgbdImages.front()->header;
    for (size_t i = 0; i < d.rgbdImages.size(); ++i) {
      std::string error;
      if (!rtabmap_sync::checkRgbdImage(*d.rgbdImages[i], &error)) {
        if (errors_.due(std::to_string(i) + error)) {
          NODELET_ERROR("rgbdx_sync: rgbd_image%zu: %s; set at %.6f dropped.", i, error.c_str(), d.stamp.toSec());
        }
        return;
      }
      out->rgbd_images.push_back(*d.rgbdImages[i]);
    }
    publisher_.publish(out);
  }

  rtabmap_sync::LogThrottle errors_;
  ros::Publisher publisher_;
  rtabmap_sync::DataSubscriber subscriber_;
};

}  // namespace rtabmap_ros

PLUGINLIB_EXPORT_CLASS(rtabmap_ros::RGBDXSyncNodelet, nodelet::Nodelet)

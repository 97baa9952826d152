// rgbd_sync: synchronises rgb/image, depth/image and rgb/camera_info into one
// rtabmap_ros/RGBDImage on `rgbd_image`, so downstream nodes subscribe to a single topic and
// never see an RGB frame paired with the wrong depth frame.
//
// Parameters (classic rtabmap_ros names):
//   approx_sync (bool, true)            ApproximateTime instead of ExactTime policy
//   approx_sync_max_interval (double, 0) max stamp spread in a set, seconds (0 = unlimited)
//   queue_size (int, 10)                synchroniser queue
//   depth_scale (double, 1.0)           multiply depth values (fix a miscalibrated sensor)
//   decimation (int, 1)                 keep one pixel in N per axis (images and camera info)
#include <cv_bridge/cv_bridge.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nodelet/nodelet.h>
#include <opencv2/imgproc.hpp>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <rtabmap_ros/RGBDImage.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <memory>

namespace rtabmap_ros {

namespace {

using ImageMsg = sensor_msgs::Image;
using InfoMsg = sensor_msgs::CameraInfo;
using ApproxPolicy = message_filters::sync_policies::ApproximateTime<ImageMsg, ImageMsg, InfoMsg>;
using ExactPolicy = message_filters::sync_policies::ExactTime<ImageMsg, ImageMsg, InfoMsg>;

// Decimation keeps one pixel in `d`; depth uses nearest-neighbour so no depth is invented by
// interpolating across an object boundary.
sensor_msgs::Image decimateImage(const ImageMsg& in, int d, bool depth, double depthScale) {
  if (d <= 1 && (!depth || depthScale == 1.0)) return in;
  cv_bridge::CvImageConstPtr ptr = cv_bridge::toCvShare(in, boost::shared_ptr<void const>(), "");  // keep encoding; `in` outlives ptr
  cv::Mat out = ptr->image;
  if (d > 1) {
    cv::resize(ptr->image, out, cv::Size(ptr->image.cols / d, ptr->image.rows / d), 0, 0,
               depth ? cv::INTER_NEAREST : cv::INTER_AREA);
  }
  if (depth && depthScale != 1.0) {
    cv::Mat scaled;
    out.convertTo(scaled, out.type(), depthScale);
    out = scaled;
  }
  cv_bridge::CvImage result(in.header, in.encoding, out);
  return *result.toImageMsg();
}

InfoMsg decimateInfo(const InfoMsg& in, int d) {
  if (d <= 1) return in;
  InfoMsg out = in;
  out.width = in.width / d;
  out.height = in.height / d;
  for (int i : {0, 2, 4, 5}) out.K[i] /= d;   // fx, cx, fy, cy
  for (int i : {0, 2, 3, 5, 6}) out.P[i] /= d;  // fx, cx, Tx*fx, fy, cy
  return out;
}

}  // namespace

class RGBDSyncNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();

    bool approxSync = true;
    int queueSize = 10;
    double maxInterval = 0.0;
    pnh.param("approx_sync", approxSync, approxSync);
    pnh.param("approx_sync_max_interval", maxInterval, maxInterval);
    pnh.param("queue_size", queueSize, queueSize);
    pnh.param("depth_scale", depthScale_, depthScale_);
    pnh.param("decimation", decimation_, decimation_);
    if (decimation_ < 1) {
      NODELET_ERROR("rgbd_sync: decimation must be >= 1 (got %d), using 1.", decimation_);
      decimation_ = 1;
    }
    if (queueSize < 1) {
      NODELET_ERROR("rgbd_sync: queue_size must be >= 1 (got %d), using 10.", queueSize);
      queueSize = 10;
    }

    rgbdPub_ = nh.advertise<rtabmap_ros::RGBDImage>("rgbd_image", 1);
    rgbSub_.subscribe(nh, "rgb/image", 1);
    depthSub_.subscribe(nh, "depth/image", 1);
    infoSub_.subscribe(nh, "rgb/camera_info", 1);

    if (approxSync) {
      approx_ = std::make_unique<message_filters::Synchronizer<ApproxPolicy>>(
          ApproxPolicy(queueSize), rgbSub_, depthSub_, infoSub_);
      if (maxInterval > 0.0) approx_->setMaxIntervalDuration(ros::Duration(maxInterval));
      approx_->registerCallback(&RGBDSyncNodelet::callback, this);
    } else {
      exact_ = std::make_unique<message_filters::Synchronizer<ExactPolicy>>(
          ExactPolicy(queueSize), rgbSub_, depthSub_, infoSub_);
      exact_->registerCallback(&RGBDSyncNodelet::callback, this);
    }
    NODELET_INFO("rgbd_sync: subscribed to %s, %s, %s (%s sync, queue %d) -> %s",
                 rgbSub_.getTopic().c_str(), depthSub_.getTopic().c_str(),
                 infoSub_.getTopic().c_str(), approxSync ? "approx" : "exact", queueSize,
                 rgbdPub_.getTopic().c_str());
  }

  void callback(const sensor_msgs::ImageConstPtr& rgb, const sensor_msgs::ImageConstPtr& depth,
                const sensor_msgs::CameraInfoConstPtr& info) {
    if (rgbdPub_.getNumSubscribers() == 0) return;
    namespace enc = sensor_msgs::image_encodings;
    if (depth->encoding != enc::TYPE_16UC1 && depth->encoding != enc::TYPE_32FC1 &&
        depth->encoding != enc::MONO16) {
      NODELET_ERROR_THROTTLE(5.0, "rgbd_sync: depth encoding \"%s\" is not 16UC1 or 32FC1; frame dropped.",
                             depth->encoding.c_str());
      return;
    }
    auto msg = boost::make_shared<rtabmap_ros::RGBDImage>();
    // The set's stamp is the RGB stamp: features and poses are taken from the colour camera.
    msg->header = rgb->header;
    try {
      msg->rgb = decimateImage(*rgb, decimation_, false, 1.0);
      msg->depth = decimateImage(*depth, decimation_, true, depthScale_);
    } catch (const cv_bridge::Exception& e) {
      NODELET_ERROR_THROTTLE(5.0, "rgbd_sync: cannot convert images (%s); frame dropped.", e.what());
      return;
    }
    msg->rgb_camera_info = decimateInfo(*info, decimation_);
    // Depth is registered to the colour camera in the rgbd_sync contract.
    msg->depth_camera_info = msg->rgb_camera_info;
    msg->depth_camera_info.header = depth->header;
    rgbdPub_.publish(msg);
  }

  double depthScale_ = 1.0;
  int decimation_ = 1;
  ros::Publisher rgbdPub_;
  message_filters::Subscriber<ImageMsg> rgbSub_;
  message_filters::Subscriber<ImageMsg> depthSub_;
  message_filters::Subscriber<InfoMsg> infoSub_;
  std::unique_ptr<message_filters::Synchronizer<ApproxPolicy>> approx_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_;
};

}  // namespace rtabmap_ros

PLUGINLIB_EXPORT_CLASS(rtabmap_ros::RGBDSyncNodelet, nodelet::Nodelet)

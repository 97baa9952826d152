#pragma once
// Output of rgbd_sync and stereo_sync, as the classic nodes publish it: `rgbd_image` (raw
// images) and `rgbd_image/compressed` (the same RGBDImage with jpeg colour and lossless depth
// or png right image, for remote links), at most `compressed_rate` Hz (0 = every frame).
// Each is encoded only when someone subscribes.
#include <ros/ros.h>
#include <rtabmap_ros/RGBDImage.h>

#include <string>

#include "rtabmap_conversions/RGBDImageConversions.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap_sync {

class RGBDPublisher {
 public:
  void advertise(ros::NodeHandle& nh, double compressedRate) {
    raw_ = nh.advertise<rtabmap_ros::RGBDImage>("rgbd_image", 1);
    compressed_ = nh.advertise<rtabmap_ros::RGBDImage>("rgbd_image/compressed", 1);
    compressedRate_ = compressedRate;
  }

  bool wanted() const { return raw_.getNumSubscribers() > 0 || compressed_.getNumSubscribers() > 0; }

  // Throws rtabmap::FormatError if the frame cannot be encoded (the caller logs and goes on).
  void publish(const rtabmap::SensorData& frame, const std_msgs::Header& header, const std::string& rightFrameId = "") {
    rtabmap_conversions::RGBDImageOptions options;
    options.rightFrameId = rightFrameId;
    if (raw_.getNumSubscribers() > 0) {
      raw_.publish(rtabmap_conversions::rgbdImageToMsg(frame, header, options));
    }
    if (compressed_.getNumSubscribers() > 0 && compressedDue(header.stamp)) {
      options.compressed = true;
      compressed_.publish(rtabmap_conversions::rgbdImageToMsg(frame, header, options));
      lastCompressed_ = header.stamp;
    }
  }

 private:
  // Throttled on the data's stamps, so a bag played faster still gets the asked rate of data.
  bool compressedDue(const ros::Time& stamp) const {
    return compressedRate_ <= 0.0 || lastCompressed_.isZero() || stamp < lastCompressed_ ||
           (stamp - lastCompressed_).toSec() >= 1.0 / compressedRate_;
  }

  ros::Publisher raw_;
  ros::Publisher compressed_;
  double compressedRate_ = 0.0;
  ros::Time lastCompressed_;
};

}  // namespace rtabmap_sync

#pragma once
// Fuzz entries of the ROS-message-to-core conversions (rtabmap_conversions). Contract as in
// rtabmap_core/test/fuzz_regressions/FuzzEntry.h: a message is converted or refused through
// the `error` string / std::nullopt (or rtabmap::Error); never a crash or another exception.
// A converted result is converted back where a writer exists, which must not crash either.
#include "rtabmap_conversions/CameraInfoConversions.h"
#include "rtabmap_conversions/LaserScanConversions.h"
#include "rtabmap_conversions/PointCloudConversions.h"
#include "rtabmap_conversions/RGBDImageConversions.h"
#include "rtabmap_core/common/Error.h"
#include "RosMessages.h"

namespace rtabmap::fuzz {

enum class RosOutcome { kAccepted, kRejected };

template <typename Body>
RosOutcome guardedRos(Body&& body) {
  try {
    return body() ? RosOutcome::kAccepted : RosOutcome::kRejected;
  } catch (const rtabmap::Error&) {
    return RosOutcome::kRejected;
  }
}

inline RosOutcome fuzzCameraInfo(const uint8_t* data, size_t size) {
  ByteReader r(data, size);
  const sensor_msgs::CameraInfo left = randomCameraInfo(r);
  const sensor_msgs::CameraInfo right = randomCameraInfo(r);
  return guardedRos([&] {
    std::string error;
    const auto model = rtabmap_conversions::cameraModelFromMsg(left, rtabmap::CameraModel::opticalRotation(), &error);
    if (model) rtabmap_conversions::cameraModelToMsg(*model, left.header);
    const auto stereo = rtabmap_conversions::stereoModelFromMsgs(left, right, rtabmap::CameraModel::opticalRotation(), &error);
    if (stereo) {
      sensor_msgs::CameraInfo l, rr;
      rtabmap_conversions::stereoModelToMsgs(*stereo, left.header, right.header, l, rr);
    }
    return model.has_value();
  });
}

inline RosOutcome fuzzLaserScan(const uint8_t* data, size_t size) {
  ByteReader r(data, size);
  const sensor_msgs::LaserScan msg = randomLaserScan(r);
  return guardedRos([&] {
    std::string error;
    const auto scan = rtabmap_conversions::laserScanFromMsg(msg, rtabmap::Transform::Identity(), &error);
    if (scan) rtabmap_conversions::laserScanToMsg(*scan, msg.header, &error);
    return scan.has_value();
  });
}

inline RosOutcome fuzzPointCloud2(const uint8_t* data, size_t size) {
  ByteReader r(data, size);
  const sensor_msgs::PointCloud2 msg = randomPointCloud2(r);
  return guardedRos([&] {
    std::string error;
    const auto scan = rtabmap_conversions::laserScanFromCloudMsg(msg, rtabmap::Transform::Identity(), &error);
    if (scan) rtabmap_conversions::laserScanToCloudMsg(*scan, msg.header);
    return scan.has_value();
  });
}

inline RosOutcome fuzzRgbdImage(const uint8_t* data, size_t size) {
  ByteReader r(data, size);
  const rtabmap_ros::RGBDImage msg = randomRgbdImage(r);
  return guardedRos([&] {
    std::string error;
    const auto sensor = rtabmap_conversions::rgbdImageFromMsg(msg, rtabmap::Transform::Identity(), &error);
    if (sensor) rtabmap_conversions::rgbdImageToMsg(*sensor, msg.header);
    return sensor.has_value();
  });
}

}  // namespace rtabmap::fuzz

#include "rtabmap_conversions/FeatureConversions.h"

#include "Support.h"
#include "rtabmap_core/codec/Compression.h"

namespace rtabmap_conversions {

rtabmap_ros::KeyPoint keypointToMsg(const cv::KeyPoint& kpt) {
  rtabmap_ros::KeyPoint msg;
  msg.pt.x = kpt.pt.x;
  msg.pt.y = kpt.pt.y;
  msg.size = kpt.size;
  msg.angle = kpt.angle;
  msg.response = kpt.response;
  msg.octave = kpt.octave;
  msg.class_id = kpt.class_id;
  return msg;
}

cv::KeyPoint keypointFromMsg(const rtabmap_ros::KeyPoint& msg) {
  return cv::KeyPoint(msg.pt.x, msg.pt.y, msg.size, msg.angle, msg.response, msg.octave, msg.class_id);
}

std::vector<rtabmap_ros::KeyPoint> keypointsToMsg(const std::vector<cv::KeyPoint>& kpts) {
  std::vector<rtabmap_ros::KeyPoint> out;
  out.reserve(kpts.size());
  for (const cv::KeyPoint& k : kpts) out.push_back(keypointToMsg(k));
  return out;
}

std::vector<cv::KeyPoint> keypointsFromMsg(const std::vector<rtabmap_ros::KeyPoint>& msgs) {
  std::vector<cv::KeyPoint> out;
  out.reserve(msgs.size());
  for (const rtabmap_ros::KeyPoint& m : msgs) out.push_back(keypointFromMsg(m));
  return out;
}

rtabmap_ros::Point3f pointToMsg(const cv::Point3f& pt) {
  rtabmap_ros::Point3f msg;
  msg.x = pt.x;
  msg.y = pt.y;
  msg.z = pt.z;
  return msg;
}

cv::Point3f pointFromMsg(const rtabmap_ros::Point3f& msg) { return cv::Point3f(msg.x, msg.y, msg.z); }

std::vector<rtabmap_ros::Point3f> pointsToMsg(const std::vector<cv::Point3f>& pts) {
  std::vector<rtabmap_ros::Point3f> out;
  out.reserve(pts.size());
  for (const cv::Point3f& p : pts) out.push_back(pointToMsg(p));
  return out;
}

std::vector<cv::Point3f> pointsFromMsg(const std::vector<rtabmap_ros::Point3f>& msgs) {
  std::vector<cv::Point3f> out;
  out.reserve(msgs.size());
  for (const rtabmap_ros::Point3f& m : msgs) out.push_back(pointFromMsg(m));
  return out;
}

std::vector<uint8_t> descriptorsToMsg(const cv::Mat& descriptors) {
  if (descriptors.empty()) return {};
  return rtabmap::codec::compressData(descriptors);
}

std::optional<cv::Mat> descriptorsFromMsg(const std::vector<uint8_t>& bytes, int expectedRows, std::string* error) {
  // Keypoints without descriptors are legal: the receiver extracts them again.
  if (bytes.empty()) return cv::Mat();
  cv::Mat descriptors;
  try {
    descriptors = rtabmap::codec::uncompressData(bytes);
  } catch (const std::exception& e) {
    return detail::fail(error, std::string("corrupt descriptors: ") + e.what());
  }
  if (expectedRows >= 0 && descriptors.rows != expectedRows) {
    return detail::fail(error, std::to_string(descriptors.rows) + " descriptors for " + std::to_string(expectedRows) +
                                   " keypoints");
  }
  return descriptors;
}

}  // namespace rtabmap_conversions

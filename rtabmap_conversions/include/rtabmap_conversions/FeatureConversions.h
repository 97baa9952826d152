#pragma once
// Visual features in messages (RGBDImage, NodeData, OdomInfo): keypoints as
// rtabmap_ros/KeyPoint, 3D points as rtabmap_ros/Point3f, and descriptors as one uint8[] that
// holds the core's zlib blob of the descriptor matrix (codec::compressData), so any descriptor
// type (binary CV_8U, float CV_32F) and size travels without a side channel for its layout.
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>
#include <rtabmap_ros/KeyPoint.h>
#include <rtabmap_ros/Point2f.h>
#include <rtabmap_ros/Point3f.h>

#include <optional>
#include <string>
#include <vector>

namespace rtabmap_conversions {

rtabmap_ros::KeyPoint keypointToMsg(const cv::KeyPoint& kpt);
cv::KeyPoint keypointFromMsg(const rtabmap_ros::KeyPoint& msg);
std::vector<rtabmap_ros::KeyPoint> keypointsToMsg(const std::vector<cv::KeyPoint>& kpts);
std::vector<cv::KeyPoint> keypointsFromMsg(const std::vector<rtabmap_ros::KeyPoint>& msgs);

rtabmap_ros::Point3f pointToMsg(const cv::Point3f& pt);
cv::Point3f pointFromMsg(const rtabmap_ros::Point3f& msg);
std::vector<rtabmap_ros::Point3f> pointsToMsg(const std::vector<cv::Point3f>& pts);
std::vector<cv::Point3f> pointsFromMsg(const std::vector<rtabmap_ros::Point3f>& msgs);

// Empty matrix -> empty bytes.
std::vector<uint8_t> descriptorsToMsg(const cv::Mat& descriptors);
// Errors: corrupt bytes, or a row count other than expectedRows (when expectedRows >= 0).
std::optional<cv::Mat> descriptorsFromMsg(const std::vector<uint8_t>& bytes, int expectedRows,
                                          std::string* error = nullptr);

}  // namespace rtabmap_conversions

#pragma once
// Features and a depth image registered to the colour image (CV_16UC1 mm or CV_32FC1 m, see
// SensorData::depthAt for what counts as invalid). The depth image may be smaller than the
// colour one by a whole factor (decimated depth, as RGB-D drivers publish it): a colour pixel
// (u, v) reads the depth pixel (u / f, v / f).
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include <vector>

namespace rtabmap {

class CameraModel;

// Whole factor f such that colour size = f x depth size in both directions; 0 if the sizes are
// not related that way (or either is empty).
int depthDecimationFactor(const cv::Size& imageSize, const cv::Size& depthSize);

// Mask of the colour image size (CV_8UC1, 255 = allowed) where the depth is valid and within
// [minDepth, maxDepth] (0 = no limit). The depth image must relate to imageSize by a whole
// factor (else std::invalid_argument). *validPixels (if given) counts the allowed depth pixels.
cv::Mat depthMask(const cv::Mat& depth, const cv::Size& imageSize, float minDepth, float maxDepth,
                  int* validPixels = nullptr);

// Depth (m) under a keypoint, or 0 when there is none to trust: invalid depth pixel, or a depth
// discontinuity in its 3x3 neighbourhood (a corner on an object's silhouette mixes foreground
// and background: its depth belongs to neither surface reliably).
float keypointDepth(const cv::Mat& depth, const cv::Point2f& imagePoint, int decimation);

// 3D points in the robot base frame (the model's local transform applied) of keypoints of the
// colour image; NaN where keypointDepth() is 0 or outside [minDepth, maxDepth] (0 = no limit).
std::vector<cv::Point3f> keypoints3DFromDepth(const std::vector<cv::KeyPoint>& keypoints,
                                              const cv::Mat& depth, const cv::Size& imageSize,
                                              const CameraModel& model, float minDepth = 0.0f,
                                              float maxDepth = 0.0f);

}  // namespace rtabmap

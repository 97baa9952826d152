#pragma once
// Sparse stereo: the right-image match of left-image keypoints in a rectified pair, hence a
// disparity per keypoint and its depth = fx * baseline / disparity.
//
// Two ways, chosen by Stereo/OpticalFlow: pyramidal Lucas-Kanade optical flow from the left to
// the right image restricted to the row (rectified images put both views of a point on the same
// row, so only the disparity is estimated, coarse to fine, to sub-pixel accuracy; a match whose
// windows correlate under 0.8 is rejected), or block matching along the same row (SSD or SAD).
// Either way a match is rejected when its disparity is not positive or outside
// [Stereo/MinDisparity, Stereo/MaxDisparity].
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include <string>
#include <vector>

#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

class StereoCameraModel;

struct StereoOptions {
  bool opticalFlow = true;
  int winWidth = 15;
  int winHeight = 3;
  int iterations = 30;
  int maxLevel = 5;
  double eps = 0.01;
  bool ssd = true;            // block matching: sum of squared (true) or absolute differences
  float minDisparity = 0.5f;  // pixels
  float maxDisparity = 128.0f;

  static StereoOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
};

// Disparity (left x - right x, pixels) of each left point in the right image; 0 where no valid
// match was found. Both images 8-bit grey of the same size (else std::invalid_argument).
std::vector<float> computeStereoDisparities(const cv::Mat& leftGrey, const cv::Mat& rightGrey,
                                            const std::vector<cv::Point2f>& leftPoints,
                                            const StereoOptions& options);

// 3D points in the robot base frame (the left camera's local transform applied) of keypoints
// with the given disparities; NaN where the disparity is 0 or the depth is outside
// [minDepth, maxDepth] (0 = no limit).
std::vector<cv::Point3f> keypoints3DFromDisparities(const std::vector<cv::KeyPoint>& keypoints,
                                                    const std::vector<float>& disparities,
                                                    const StereoCameraModel& model,
                                                    float minDepth = 0.0f, float maxDepth = 0.0f);

}  // namespace rtabmap

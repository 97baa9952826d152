#pragma once
// The OpenCV detectors and descriptors behind each FeatureType, built from the detector
// groups' parameters (GFTT/, ORB/, SIFT/, FAST/, BRISK/, KAZE/, BRIEF/).
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include <vector>

#include "rtabmap_core/features/FeatureDetector.h"

namespace rtabmap::features_detail {

class OpenCvFeatures {
 public:
  OpenCvFeatures(FeatureType type, const ParametersMap& detectorParameters);

  // Keypoints of one grey image (or cell) where mask allows, at most maxKeypoints (0 = no
  // limit), the strongest first.
  std::vector<cv::KeyPoint> detect(const cv::Mat& grey, const cv::Mat& mask, int maxKeypoints) const;
  // Descriptors; keypoints without one are removed.
  cv::Mat compute(const cv::Mat& grey, std::vector<cv::KeyPoint>& keypoints) const;

 private:
  std::vector<cv::KeyPoint> detectFast(const cv::Mat& grey, const cv::Mat& mask, int maxKeypoints) const;

  FeatureType type_;
  ParametersMap p_;
  cv::Ptr<cv::Feature2D> detector_;    // built once, for detectors without a count limit to set
  cv::Ptr<cv::Feature2D> descriptor_;
  bool rootSift_ = false;
};

}  // namespace rtabmap::features_detail

// BRIEF (written here, no xfeatures2d): deterministic, discriminative, tolerant to small shifts.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "odometry/SyntheticRoom.h"
#include "rtabmap_core/features/FeatureDetector.h"

namespace rtabmap {
namespace {

using test::SyntheticRoom;

int hamming(const cv::Mat& a, int i, const cv::Mat& b, int j) {
  return static_cast<int>(cv::norm(a.row(i), b.row(j), cv::NORM_HAMMING));
}

TEST(Brief, DeterministicLengthAndType) {
  SyntheticRoom room;
  const SensorData data = room.rgbd(Transform(0, 0, 1.2, 0, 0, 0.2), SyntheticRoom::camera());
  for (int bytes : {16, 32, 64}) {
    const ParametersMap p{{"Vis/FeatureType", "6"}, {"BRIEF/Bytes", std::to_string(bytes)}};
    const ImageFeatures a = FeatureDetector::create(p, FeatureGroup::kVis)->extract(data);
    const ImageFeatures b = FeatureDetector::create(p, FeatureGroup::kVis)->extract(data);
    ASSERT_GT(a.size(), 100u);
    EXPECT_EQ(a.descriptors.cols, bytes);
    EXPECT_EQ(a.descriptors.type(), CV_8U);
    EXPECT_EQ(cv::norm(a.descriptors, b.descriptors, cv::NORM_HAMMING), 0.0);
  }
}

TEST(Brief, MatchesSurviveAShiftAndDifferFromOthers) {
  SyntheticRoom room;
  const SensorData data = room.rgbd(Transform(0, 0, 1.2, 0, 0, 0.2), SyntheticRoom::camera());
  auto detector = FeatureDetector::create({{"Vis/FeatureType", "6"}}, FeatureGroup::kVis);
  cv::Mat grey;
  cv::cvtColor(data.imageRaw(), grey, cv::COLOR_BGR2GRAY);
  std::vector<cv::KeyPoint> k1 = detector->detect(grey);
  const cv::Mat d1 = detector->compute(grey, k1);
  // The same image shifted by (3, 2) pixels, keypoints shifted with it.
  cv::Mat shifted;
  const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, 3, 0, 1, 2);
  cv::warpAffine(grey, shifted, M, grey.size());
  std::vector<cv::KeyPoint> k2 = k1;
  for (auto& k : k2) k.pt += cv::Point2f(3, 2);
  const cv::Mat d2 = detector->compute(shifted, k2);
  ASSERT_GT(k2.size(), 50u);
  // Pair descriptors by position.
  double same = 0.0, other = 0.0;
  int n = 0;
  for (size_t j = 0; j < k2.size(); ++j) {
    for (size_t i = 0; i < k1.size(); ++i) {
      if (cv::norm(k1[i].pt + cv::Point2f(3, 2) - k2[j].pt) < 1e-3) {
        same += hamming(d1, static_cast<int>(i), d2, static_cast<int>(j));
        other += hamming(d1, static_cast<int>((i + 7) % k1.size()), d2, static_cast<int>(j));
        ++n;
        break;
      }
    }
  }
  ASSERT_GT(n, 50);
  EXPECT_LT(same / n, 5.0);    // the same corner: almost identical bits (interpolation noise only)
  EXPECT_GT(other / n, 70.0);  // another corner: about half of 256 bits differ
}

}  // namespace
}  // namespace rtabmap

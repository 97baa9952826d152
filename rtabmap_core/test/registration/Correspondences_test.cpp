// Correspondences: NNDR matching over every search structure, guided matching in a window,
// optical flow.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <limits>
#include <random>

#include "odometry/SyntheticRoom.h"
#include "common/TestData.h"
#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/registration/Correspondences.h"

namespace rtabmap {
namespace {

// n random descriptors, and a noisy copy of them in shuffled order; returns the permutation.
std::vector<int> descriptorPair(bool binary, int n, cv::Mat& from, cv::Mat& to) {
  cv::RNG rng(rtabmap::test::drawSeed(42));
  from.create(n, binary ? 32 : 64, binary ? CV_8U : CV_32F);
  if (binary) {
    rng.fill(from, cv::RNG::UNIFORM, 0, 256);
  } else {
    rng.fill(from, cv::RNG::UNIFORM, 0.0f, 1.0f);
  }
  std::vector<int> perm(static_cast<size_t>(n));
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(rtabmap::test::drawSeed(1)));
  to.create(n, from.cols, from.type());
  for (int i = 0; i < n; ++i) {
    from.row(perm[static_cast<size_t>(i)]).copyTo(to.row(i));
    if (binary) {
      to.at<unsigned char>(i, i % 32) ^= 0x11;  // flip 2 bits
    } else {
      to.at<float>(i, i % 64) += 0.05f;
    }
  }
  return perm;
}

TEST(Correspondences, NndrMatchingOverEverySearch) {
  for (bool binary : {true, false}) {
    cv::Mat from, to;
    const std::vector<int> perm = descriptorPair(binary, 300, from, to);
    for (int type : {0, 1, 2, 3, 5}) {
      CorrespondenceOptions o;
      o.nnType = static_cast<NearestNeighborType>(type);
      const std::vector<cv::DMatch> m = matchDescriptors(from, to, o);
      SCOPED_TRACE(std::string(binary ? "binary" : "float") + " type " + std::to_string(type));
      // LSH is approximate: it often returns a single neighbour, and the ratio test needs two.
      EXPECT_GT(m.size(), binary && type == 2 ? 120u : 270u);
      int correct = 0;
      for (const cv::DMatch& d : m) correct += perm[static_cast<size_t>(d.trainIdx)] == d.queryIdx ? 1 : 0;
      EXPECT_EQ(correct, static_cast<int>(m.size()));
    }
  }
  cv::Mat a(3, 32, CV_8U), b(3, 64, CV_32F);
  EXPECT_THROW(matchDescriptors(a, b, CorrespondenceOptions()), std::invalid_argument);
}

TEST(Correspondences, NndrRejectsAmbiguousMatches) {
  cv::Mat from(2, 4, CV_32F), to(1, 4, CV_32F);
  from.row(0).setTo(0.0f);
  from.row(1).setTo(0.0f);
  from.at<float>(1, 0) = 0.01f;  // two nearly identical references
  to.setTo(0.0f);
  to.at<float>(0, 1) = 0.5f;
  CorrespondenceOptions o;
  o.nnType = NearestNeighborType::kBruteForce;
  EXPECT_TRUE(matchDescriptors(from, to, o).empty());
  o.nnType = NearestNeighborType::kBruteForceCrossCheck;  // mutual nearest: no ratio test
  EXPECT_EQ(matchDescriptors(from, to, o).size(), 1u);
}

TEST(Correspondences, GuidedMatchingSearchesOnlyTheWindow) {
  cv::Mat from, to;
  const std::vector<int> perm = descriptorPair(true, 100, from, to);
  // `to` keypoints on a grid; each reference projected where its true match is, except the
  // first 10 projected 100 px away.
  std::vector<cv::KeyPoint> keypoints;
  for (int i = 0; i < 100; ++i) keypoints.emplace_back(cv::Point2f(20.0f + 50.0f * (i % 10), 20.0f + 50.0f * (i / 10)), 7.0f);
  std::vector<cv::Point2f> projected(100);
  for (int i = 0; i < 100; ++i) {
    projected[static_cast<size_t>(perm[static_cast<size_t>(i)])] = keypoints[static_cast<size_t>(i)].pt + cv::Point2f(3.0f, -2.0f);
  }
  for (int i = 0; i < 10; ++i) projected[static_cast<size_t>(perm[static_cast<size_t>(i)])] += cv::Point2f(100.0f, 0.0f);
  projected[static_cast<size_t>(perm[99])] = cv::Point2f(std::numeric_limits<float>::quiet_NaN(), 0.0f);
  for (bool toProjection : {false, true}) {
    CorrespondenceOptions o;
    o.guessMatchToProjection = toProjection;
    const std::vector<cv::DMatch> m = matchByProjection(projected, from, keypoints, to, 20.0f, o);
    int correct = 0;
    for (const cv::DMatch& d : m) correct += perm[static_cast<size_t>(d.trainIdx)] == d.queryIdx ? 1 : 0;
    EXPECT_EQ(correct, static_cast<int>(m.size()));
    EXPECT_EQ(m.size(), 89u) << "guessMatchToProjection " << toProjection;
  }
}

TEST(Correspondences, WordIdsPairOnlyWordsSeenOnceInEachFrame) {
  // from: 3 twice (which keypoint?), 4 not in `to`; to: 1 twice.
  const std::vector<int> fromIds{1, 2, 3, 3, 4, 5, 6};
  const std::vector<int> toIds{5, 3, 2, 9, 1, 1, 6};
  std::vector<cv::DMatch> m = matchByWordIds(fromIds, toIds, {}, {}, 0.0f);
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0].queryIdx, 1);  // word 2
  EXPECT_EQ(m[0].trainIdx, 2);
  EXPECT_EQ(m[1].queryIdx, 5);  // word 5
  EXPECT_EQ(m[1].trainIdx, 0);
  EXPECT_EQ(m[2].queryIdx, 6);  // word 6
  EXPECT_EQ(m[2].trainIdx, 6);
  // With projections: word 2 lands 30 px from its keypoint, word 5 within the radius, word 6
  // does not project.
  std::vector<cv::KeyPoint> keypoints;
  for (int j = 0; j < 7; ++j) keypoints.emplace_back(cv::Point2f(10.0f * j, 5.0f), 7.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<cv::Point2f> projected(7, cv::Point2f(0.0f, 0.0f));
  projected[1] = keypoints[2].pt + cv::Point2f(30.0f, 0.0f);
  projected[5] = keypoints[0].pt + cv::Point2f(3.0f, 4.0f);
  projected[6] = cv::Point2f(nan, nan);
  m = matchByWordIds(fromIds, toIds, projected, keypoints, 20.0f);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].queryIdx, 5);
  EXPECT_EQ(m[0].trainIdx, 0);
  EXPECT_THROW(matchByWordIds(fromIds, toIds, projected, {}, 20.0f), std::invalid_argument);
}

TEST(Correspondences, OpticalFlowFollowsAShift) {
  test::SyntheticRoom room;
  const SensorData data = room.rgbd(Transform(0, 0, 1.2, 0, 0, 0.3), test::SyntheticRoom::camera());
  cv::Mat grey, shifted;
  cv::cvtColor(data.imageRaw(), grey, cv::COLOR_BGR2GRAY);
  const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, 6.5, 0, 1, -4.0);
  cv::warpAffine(grey, shifted, M, grey.size());
  std::vector<cv::Point2f> points;
  cv::KeyPoint::convert(FeatureDetector::create({}, FeatureGroup::kVis)->detect(grey), points);
  // Tracked (status set) and tracked within 0.3 pixel of the true shift, with the
  // forward-backward check at `backCheck` pixels (0 = off).
  auto track = [&](float backCheck) {
    CorrespondenceOptions options;
    options.flowBackCheck = backCheck;
    std::vector<unsigned char> status;
    const std::vector<cv::Point2f> tracked = trackOpticalFlow(grey, shifted, points, {}, options, status);
    std::pair<int, int> okGood{0, 0};
    for (size_t i = 0; i < points.size(); ++i) {
      if (!status[i]) continue;
      ++okGood.first;
      okGood.second += cv::norm(tracked[i] - points[i] - cv::Point2f(6.5f, -4.0f)) < 0.3 ? 1 : 0;
    }
    return okGood;
  };
  const auto [okAll, goodAll] = track(0.0f);
  const auto [okChecked, goodChecked] = track(1.0f);
  EXPECT_GT(okAll, static_cast<int>(points.size()) * 8 / 10);
  EXPECT_GT(goodAll, okAll * 9 / 10);
  // The forward-backward check keeps the right tracks.
  EXPECT_GT(okChecked, static_cast<int>(points.size()) * 8 / 10);
  EXPECT_GT(goodChecked, okChecked * 9 / 10);
}

}  // namespace
}  // namespace rtabmap

// Epipolar verification of a loop-closure hypothesis (VhEp): two views of one rigid scene pass,
// an alias (the same words in another arrangement, or only repeated words) does not.
#include "rtabmap_core/memory/EpipolarCheck.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include <algorithm>
#include <map>
#include <numeric>
#include <random>

#include "common/TestData.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/memory/Signature.h"

namespace rtabmap::memory {
namespace {

// A scene of n points 3-8 m in front of the first camera, seen by a pinhole camera (f 500,
// 640 x 480) from `motion` (camera frame: x right, y down, z forward). Another scene on each
// test draw (RTABMAP_TEST_DRAW).
std::vector<cv::Point3f> scene(int n, unsigned seed) {
  cv::RNG rng(test::drawSeed(seed));
  std::vector<cv::Point3f> points;
  for (int i = 0; i < n; ++i) {
    // Braces: drawn in order.
    points.push_back(cv::Point3f{rng.uniform(-2.5f, 2.5f), rng.uniform(-1.8f, 1.8f), rng.uniform(3.f, 8.f)});
  }
  return points;
}

std::vector<cv::KeyPoint> project(const std::vector<cv::Point3f>& points, const cv::Matx33f& r, const cv::Vec3f& t) {
  std::vector<cv::KeyPoint> kpts;
  for (const cv::Point3f& p : points) {
    const cv::Vec3f c = r * cv::Vec3f(p.x, p.y, p.z) + t;
    kpts.emplace_back(500.f * c[0] / c[2] + 320.f, 500.f * c[1] / c[2] + 240.f, 7.f);
  }
  return kpts;
}

cv::Matx33f yaw(float radians) {
  const float c = std::cos(radians), s = std::sin(radians);
  return {c, 0, s, 0, 1, 0, -s, 0, c};
}

// A location whose keypoint i is word wordOf[i].
Signature location(int id, const std::vector<cv::KeyPoint>& kpts, const std::vector<int>& wordOf) {
  std::multimap<int, int> words;
  for (size_t i = 0; i < kpts.size(); ++i) words.emplace(wordOf[i], static_cast<int>(i));
  Signature s(id);
  s.setWords(words, kpts, {}, cv::Mat());
  return s;
}

std::vector<int> distinctWords(int n) {
  std::vector<int> w(static_cast<size_t>(n));
  std::iota(w.begin(), w.end(), 1);
  return w;
}

EpipolarCheckOptions defaults() { return EpipolarCheckOptions::fromParameters({}); }

TEST(EpipolarCheck, TwoViewsOfOneSceneAgree) {
  const auto points = scene(120, 1);
  const Signature a = location(1, project(points, cv::Matx33f::eye(), {0, 0, 0}), distinctWords(120));
  const Signature b = location(2, project(points, yaw(0.15f), {0.4f, 0.f, -0.3f}), distinctWords(120));
  const EpipolarCheckSummary r = checkEpipolarGeometry(a, b, defaults());
  EXPECT_TRUE(r.accepted) << r.Summary();
  EXPECT_EQ(r.pairs, 120);
  EXPECT_GE(r.inliers, 118);
}

TEST(EpipolarCheck, TheSameWordsInAnotherArrangementAreRefused) {
  // An alias: the words of the first view, but where another scene puts them. A fitted F
  // agrees by chance with its 7-pair sample and a few more: 10-11 of 40 pairs here, 13 of 120,
  // above VhEp/MatchCountMin, so the inlier ratio decides.
  const auto points = scene(120, 1);
  const Signature a = location(1, project(points, cv::Matx33f::eye(), {0, 0, 0}), distinctWords(120));
  for (int n : {40, 120}) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      std::vector<int> shuffled = distinctWords(120);
      std::shuffle(shuffled.begin(), shuffled.begin() + n, std::mt19937(test::drawSeed(seed)));
      std::vector<cv::KeyPoint> kpts = project(points, yaw(0.15f), {0.4f, 0.f, -0.3f});
      kpts.resize(static_cast<size_t>(n));
      shuffled.resize(static_cast<size_t>(n));
      const Signature b = location(2, kpts, shuffled);
      const EpipolarCheckSummary r = checkEpipolarGeometry(a, b, defaults());
      EXPECT_FALSE(r.accepted) << n << " pairs, shuffle " << seed << ": " << r.Summary();
      EXPECT_EQ(r.pairs, n);
      EXPECT_GE(r.inliers, 8) << "the count alone (VhEp/MatchCountMin) would accept it";
      EXPECT_NE(r.Summary().find("agree"), std::string::npos) << r.Summary();
    }
  }
}

TEST(EpipolarCheck, TrueViewWithManyWrongPairsStillAgrees) {
  // Word quantisation pairs some keypoints wrongly: 40% of the pairs here are wrong.
  const auto points = scene(150, 3);
  std::vector<int> words = distinctWords(150);
  const Signature a = location(1, project(points, cv::Matx33f::eye(), {0, 0, 0}), words);
  std::vector<int> noisy = words;
  std::shuffle(noisy.begin(), noisy.begin() + 60, std::mt19937(test::drawSeed(11)));
  const Signature b = location(2, project(points, yaw(-0.1f), {-0.3f, 0.05f, 0.5f}), noisy);
  const EpipolarCheckSummary r = checkEpipolarGeometry(a, b, defaults());
  EXPECT_TRUE(r.accepted) << r.Summary();
  EXPECT_GE(r.inliers, 90);
  EXPECT_LE(r.inliers, 100);
  // With the ratio raised above the right pairs' share, the same view is refused.
  EpipolarCheckOptions strict = defaults();
  strict.inlierRatioMin = 0.8f;
  EXPECT_FALSE(checkEpipolarGeometry(a, b, strict).accepted);  // the 90 right pairs and a few wrong ones near their epipolar lines
}

TEST(EpipolarCheck, RepeatedWordsPairNothing) {
  // A tiled texture: every word three times in each image, in a consistent geometry even.
  const auto points = scene(90, 5);
  std::vector<int> words(90);
  for (int i = 0; i < 90; ++i) words[static_cast<size_t>(i)] = 1 + i / 3;
  const Signature a = location(1, project(points, cv::Matx33f::eye(), {0, 0, 0}), words);
  const Signature b = location(2, project(points, yaw(0.1f), {0.2f, 0.f, 0.f}), words);
  const EpipolarCheckSummary r = checkEpipolarGeometry(a, b, defaults());
  EXPECT_FALSE(r.accepted);
  EXPECT_EQ(r.pairs, 0);
  EXPECT_NE(r.why.find("too few unique-word pairs"), std::string::npos) << r.why;
}

TEST(EpipolarCheck, TooFewPairsAreRefusedBeforeFitting) {
  const auto points = scene(7, 9);
  const Signature a = location(1, project(points, cv::Matx33f::eye(), {0, 0, 0}), distinctWords(7));
  const Signature b = location(2, project(points, yaw(0.1f), {0.2f, 0.f, 0.f}), distinctWords(7));
  EXPECT_FALSE(checkEpipolarGeometry(a, b, defaults()).accepted);
  EXPECT_FALSE(checkEpipolarGeometry(a, Signature(3), defaults()).accepted);  // no words at all
}

TEST(EpipolarCheck, OptionsComeFromTheParametersAndAreChecked) {
  const auto o = EpipolarCheckOptions::fromParameters(
      {{"VhEp/Enabled", "true"}, {"VhEp/MatchCountMin", "20"}, {"VhEp/InlierRatioMin", "0.5"},
       {"VhEp/RansacParam1", "1.5"}, {"VhEp/RansacParam2", "0.9"}});
  EXPECT_TRUE(o.enabled);
  EXPECT_EQ(o.matchCountMin, 20);
  EXPECT_FLOAT_EQ(o.inlierRatioMin, 0.5f);
  EXPECT_FLOAT_EQ(o.ransacParam1, 1.5f);
  EXPECT_FLOAT_EQ(o.ransacParam2, 0.9f);
  EpipolarCheckOptions bad = o;
  bad.matchCountMin = 7;
  std::string why;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("VhEp/MatchCountMin"), std::string::npos);
  bad = o;
  bad.inlierRatioMin = 1.5f;
  EXPECT_FALSE(bad.IsValid());
  bad = o;
  bad.ransacParam1 = 0.f;
  EXPECT_FALSE(bad.IsValid());
  bad = o;
  bad.ransacParam2 = 1.f;
  EXPECT_FALSE(bad.IsValid());
  EXPECT_THROW(EpipolarCheckOptions::fromParameters({{"VhEp/MatchCountMin", "3"}}), Error);
}

}  // namespace
}  // namespace rtabmap::memory

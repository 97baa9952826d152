// Bundle adjustment with Ceres pulls perturbed poses and points back to a consistent solution.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "common/TestData.h"
#include "rtabmap_core/registration/BundleAdjustment.h"

namespace rtabmap {
namespace {

const CameraModel kCamera(525.0, 525.0, 319.5, 239.5, CameraModel::opticalRotation(), 0.0, cv::Size(640, 480));

struct Scene {
  std::map<int, BundleAdjustmentFrame> frames;
  std::map<int, cv::Point3f> points;
  std::vector<BundleAdjustmentObservation> observations;
  std::map<int, Transform> truePoses;
  std::map<int, cv::Point3f> truePoints;
};

// Reprojection error (px) of an observation with the scene's current poses and points.
double pixelError(const Scene& s, const BundleAdjustmentObservation& o) {
  const Eigen::Isometry3d cw = (s.frames.at(o.frame).pose * kCamera.localTransform()).inverse().toEigen();
  const cv::Point3f& p = s.points.at(o.point);
  const Eigen::Vector3d c = cw * Eigen::Vector3d(p.x, p.y, p.z);
  double u, v;
  if (!kCamera.reproject(c.x(), c.y(), c.z(), u, v)) return std::numeric_limits<double>::infinity();
  return std::hypot(u - o.uv.x, v - o.uv.y);
}

// Five frames moving sideways along y, looking along x at points 2-5 m ahead.
Scene makeScene(bool withDepth, std::mt19937& rng) {
  Scene s;
  std::uniform_real_distribution<float> x(2.0f, 5.0f), y(-2.0f, 2.5f), z(-1.0f, 1.0f);
  for (int i = 0; i < 150; ++i) s.truePoints[i] = cv::Point3f{x(rng), y(rng), z(rng)};  // braces: drawn in order
  for (int f = 0; f < 5; ++f) s.truePoses[f] = Transform(0.05 * f, 0.1 * f, 0.0, 0.0, 0.0, 0.02 * f);
  std::normal_distribution<float> pixel(0.0f, 0.3f);
  for (const auto& [f, pose] : s.truePoses) {
    const Eigen::Isometry3d cw = (pose * kCamera.localTransform()).inverse().toEigen();
    for (const auto& [id, p] : s.truePoints) {
      const Eigen::Vector3d c = cw * Eigen::Vector3d(p.x, p.y, p.z);
      double u, v;
      if (!kCamera.reproject(c.x(), c.y(), c.z(), u, v) || u < 0 || v < 0 || u >= 640 || v >= 480) continue;
      s.observations.push_back({f, id, cv::Point2f{static_cast<float>(u) + pixel(rng), static_cast<float>(v) + pixel(rng)},
                                withDepth ? static_cast<float>(c.z()) : 0.0f});
    }
  }
  return s;
}

TEST(BundleAdjustment, RecoversPerturbedPosesAndPoints) {
  std::mt19937 rng(test::drawSeed(1));
  Scene s = makeScene(true, rng);
  std::normal_distribution<double> dt(0.0, 0.03), dr(0.0, 0.01);
  std::normal_distribution<float> dp(0.0f, 0.05f);
  for (const auto& [f, pose] : s.truePoses) {
    const bool fixed = f == 0;
    const Transform start = fixed ? pose : pose * Transform{dt(rng), dt(rng), dt(rng), dr(rng), dr(rng), dr(rng)};
    s.frames[f] = {start, kCamera, fixed, 0.0};
  }
  for (const auto& [id, p] : s.truePoints) s.points[id] = p + cv::Point3f{dp(rng), dp(rng), dp(rng)};
  const std::map<int, cv::Point3f> start = s.points;
  const BundleAdjustmentSummary summary = bundleAdjust(s.frames, s.points, s.observations);
  ASSERT_TRUE(summary.success) << summary.message;
  EXPECT_LT(summary.finalRmsePx, summary.initialRmsePx / 5);
  // A point that only the fixed frame sees moves no free pose, so it is left where it was (with
  // its perturbation: its observations keep pixels of error, and how many such points a draw
  // makes decides the summary's RMSE). Every other observation fits to about the 0.3 px noise on
  // each coordinate (several views of a point pinned by its exact depth).
  std::set<int> seenByFree;
  for (const auto& o : s.observations) {
    if (o.frame != 0) seenByFree.insert(o.point);
  }
  double squared = 0.0;
  size_t adjusted = 0;
  for (const auto& o : s.observations) {
    if (seenByFree.count(o.point) == 0) {
      EXPECT_EQ(s.points[o.point], start.at(o.point)) << "point " << o.point << " is seen by the fixed frame only";
      continue;
    }
    squared += std::pow(pixelError(s, o), 2);
    ++adjusted;
  }
  ASSERT_GT(adjusted, 400u);
  EXPECT_LT(std::sqrt(squared / static_cast<double>(adjusted)), 0.6);
  for (const auto& [f, frame] : s.frames) {
    EXPECT_LT(frame.pose.getDistance(s.truePoses[f]), 0.01) << "frame " << f;
    EXPECT_LT((frame.pose.inverse() * s.truePoses[f]).getAngle(), 0.003) << "frame " << f;
  }
  double pointError = 0.0;
  for (const auto& [id, p] : s.points) pointError += cv::norm(p - s.truePoints[id]);
  EXPECT_LT(pointError / s.points.size(), 0.03);
}

TEST(BundleAdjustment, MotionOnlyKeepsPointsAndFlagsOutliers) {
  std::mt19937 rng(test::drawSeed(2));
  Scene s = makeScene(false, rng);
  s.frames[0] = {s.truePoses[0], kCamera, true, 0.0};
  s.frames[1] = {s.truePoses[1] * Transform(0.02, -0.02, 0.01, 0, 0, 0.01), kCamera, false, 0.0};
  for (const auto& [id, p] : s.truePoints) s.points[id] = p;
  // Keep frame 1's observations, corrupt a few of them.
  std::vector<BundleAdjustmentObservation> obs;
  for (const auto& o : s.observations) {
    if (o.frame == 1) obs.push_back(o);
  }
  for (size_t i = 0; i < 5; ++i) obs[i].uv += cv::Point2f(40.0f, -30.0f);
  BundleAdjustmentOptions options;
  options.optimizePoints = false;
  const BundleAdjustmentSummary summary = bundleAdjust(s.frames, s.points, obs, options);
  ASSERT_TRUE(summary.success) << summary.message;
  EXPECT_LT(s.frames[1].pose.getDistance(s.truePoses[1]), 0.01);
  for (const auto& [id, p] : s.points) EXPECT_EQ(p, s.truePoints[id]);
  EXPECT_GE(summary.outliers.size(), 5u);
  EXPECT_LE(summary.outliers.size(), 7u);
}

TEST(BundleAdjustment, RefusesAFloatingProblem) {
  std::mt19937 rng(test::drawSeed(3));
  Scene s = makeScene(true, rng);
  for (const auto& [f, pose] : s.truePoses) s.frames[f] = {pose, kCamera, false, 0.0};
  s.points = s.truePoints;
  const BundleAdjustmentSummary summary = bundleAdjust(s.frames, s.points, s.observations);
  EXPECT_FALSE(summary.success);
  EXPECT_NE(summary.message.find("fixed"), std::string::npos);
  BundleAdjustmentOptions bad;
  bad.iterations = 0;
  std::string why;
  EXPECT_FALSE(bad.IsValid(&why));
}

}  // namespace
}  // namespace rtabmap

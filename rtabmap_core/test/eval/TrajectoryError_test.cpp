// ATE, RPE and KITTI error against values computed by hand.
#include "rtabmap_core/eval/TrajectoryError.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rtabmap_core/common/Error.h"

using rtabmap::AteOptions;
using rtabmap::FormatError;
using rtabmap::RpeOptions;
using rtabmap::Trajectory;
using rtabmap::TrajectoryAlignment;
using rtabmap::Transform;

namespace {

Trajectory wiggly(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 0.05);
  Trajectory t;
  double x = 0, y = 0, z = 0, yaw = 0;
  for (size_t i = 0; i < n; ++i) {
    yaw += 0.05 + g(rng);
    x += std::cos(yaw) * 0.3;
    y += std::sin(yaw) * 0.3;
    z += g(rng);
    t.add(100.0 + 0.1 * static_cast<double>(i), Transform{x, y, z, g(rng), g(rng), yaw});
  }
  return t;
}

}  // namespace

TEST(ErrorStats, ByHand) {
  const rtabmap::ErrorStats s = rtabmap::computeErrorStats({3.0, 1.0, 2.0, 6.0});
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 3.0);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(50.0 / 4.0));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt((0.0 + 4.0 + 1.0 + 9.0) / 4.0));
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 6.0);
  EXPECT_EQ(rtabmap::computeErrorStats({}).count, 0u);
}

TEST(Association, ClosestPairsFirstEachPoseOnce) {
  Trajectory a, b;
  for (double s : {1.0, 2.0, 3.0, 4.0}) a.add(s, Transform::Identity());
  for (double s : {1.015, 1.005, 2.03, 3.01, 3.99}) b.add(s, Transform::Identity());
  b.poses[4].pose = Transform();  // null: never associated
  const auto pairs = rtabmap::associateByStamp(a, b, 0.02);
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0], std::make_pair(size_t(0), size_t(1)));  // 1.005 beats 1.015 (b unsorted)
  EXPECT_EQ(pairs[1], std::make_pair(size_t(2), size_t(3)));
  EXPECT_EQ(rtabmap::associateByStamp(a, b, 0.05).size(), 3u);  // 2.03 joins
}

TEST(Ate, ByHandWithoutAlignment) {
  Trajectory gt, est;
  for (int i = 0; i < 4; ++i) gt.add(i, Transform(i, 0, 0));
  est.add(0.0, Transform(0, 0, 0));
  est.add(1.0, Transform(1, 0.1, 0));
  est.add(2.0, Transform(2, -0.1, 0));
  est.add(3.0, Transform(3, 0, 0));
  AteOptions options;
  options.alignment = TrajectoryAlignment::kNone;
  const auto r = rtabmap::computeAte(gt, est, options);
  EXPECT_EQ(r.pairs.size(), 4u);
  EXPECT_NEAR(r.translation.rmse, std::sqrt(0.02 / 4), 1e-12);
  EXPECT_NEAR(r.translation.mean, 0.05, 1e-12);
  EXPECT_NEAR(r.translation.median, 0.05, 1e-12);
  EXPECT_NEAR(r.translation.max, 0.1, 1e-12);
  EXPECT_NEAR(r.translation.std, 0.05, 1e-12);
}

TEST(Ate, ByHandWithRigidAndSimilarityAlignment) {
  // A unit square, and the same square 20% larger about its centre, rotated and moved away:
  // the rigid alignment can only undo the motion, leaving each corner 0.2 * sqrt(0.5) off;
  // the similarity alignment undoes everything, with scale 1 / 1.2.
  const double corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const Transform away(10, -4, 2, 0.3, -0.2, 1.1);
  Trajectory gt, est;
  for (int i = 0; i < 4; ++i) {
    gt.add(i, Transform(corners[i][0], corners[i][1], 0, 0, 0, 0));
    const double x = 0.5 + 1.2 * (corners[i][0] - 0.5), y = 0.5 + 1.2 * (corners[i][1] - 0.5);
    est.add(i, away * Transform(x, y, 0, 0, 0, 0));
  }
  auto r = rtabmap::computeAte(gt, est);
  const double e = 0.2 * std::sqrt(0.5);
  EXPECT_NEAR(r.translation.rmse, e, 1e-9);
  EXPECT_NEAR(r.translation.max, e, 1e-9);
  EXPECT_NEAR(r.translation.std, 0.0, 1e-9);
  EXPECT_NEAR(r.scale, 1.0, 0.0);
  AteOptions sim;
  sim.alignment = TrajectoryAlignment::kSim3;
  r = rtabmap::computeAte(gt, est, sim);
  EXPECT_NEAR(r.translation.rmse, 0.0, 1e-9);
  EXPECT_NEAR(r.scale, 1.0 / 1.2, 1e-9);
  // The alignment maps the estimate onto the ground truth.
  const Trajectory aligned = rtabmap::applyAlignment(est, r.alignment, r.scale);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_LT((aligned[i].pose.translation() - gt[i].pose.translation()).norm(), 1e-9);
  }
}

TEST(Ate, TrajectoryAgainstItselfAfterRigidTransformIsZero) {
  const Trajectory gt = wiggly(200, 3);
  const Transform T(3.5, -20.0, 1.25, 0.4, -0.7, 2.9);
  Trajectory est;
  for (const auto& p : gt.poses) est.add(p.stamp + 0.004, T * p.pose);  // stamps 4 ms off
  auto r = rtabmap::computeAte(gt, est);
  EXPECT_EQ(r.pairs.size(), 200u);
  EXPECT_LT(r.translation.rmse, 1e-9);
  EXPECT_LT(r.translation.max, 1e-9);
  EXPECT_LT((r.alignment * T).getNorm(), 1e-9);  // alignment = T^-1
  EXPECT_LT((r.alignment * T).getAngle(), 1e-9);
  // Sim3: also a scale.
  Trajectory scaled;
  for (const auto& p : gt.poses) {
    Eigen::Isometry3d m = p.pose.toEigen();
    m.translation() *= 0.37;
    scaled.add(p.stamp, T * Transform(m));
  }
  AteOptions sim;
  sim.alignment = TrajectoryAlignment::kSim3;
  r = rtabmap::computeAte(gt, scaled, sim);
  EXPECT_LT(r.translation.rmse, 1e-8);
  EXPECT_NEAR(r.scale, 1.0 / 0.37, 1e-9);
  // Without alignment the moved trajectory is far off.
  AteOptions none;
  none.alignment = TrajectoryAlignment::kNone;
  EXPECT_GT(rtabmap::computeAte(gt, est, none).translation.rmse, 1.0);
  // RPE and KITTI only look at relative motion: zero without any alignment.
  EXPECT_LT(rtabmap::computeRpe(gt, est).translation.max, 1e-9);
  EXPECT_LT(rtabmap::computeRpe(gt, est).rotation.max, 1e-6);
}

TEST(Ate, TooFewAssociatedPosesIsAnError) {
  Trajectory gt, est;
  gt.add(0.0, Transform::Identity());
  gt.add(1.0, Transform(1, 0, 0));
  est.add(10.0, Transform::Identity());
  est.add(11.0, Transform(1, 0, 0));
  try {
    rtabmap::computeAte(gt, est);
    ADD_FAILURE();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("0 poses associated"), std::string::npos) << e.what();
  }
}

TEST(Rpe, ByHandPerFrameAndPerMetre) {
  Trajectory gt, est;
  for (int i = 0; i < 4; ++i) gt.add(i, Transform(i, 0, 0));
  est.add(0.0, Transform(0, 0, 0));
  est.add(1.0, Transform(1, 0, 0));
  est.add(2.0, Transform(2.1, 0, 0));
  est.add(3.0, Transform(3.1, 0, 0.1));  // yaw 0.1 rad
  auto r = rtabmap::computeRpe(gt, est);
  // Pairs (0,1): exact; (1,2): 0.1 m too far; (2,3): right distance, 0.1 rad turn.
  EXPECT_EQ(r.translation.count, 3u);
  EXPECT_NEAR(r.translation.rmse, std::sqrt(0.01 / 3), 1e-12);
  EXPECT_NEAR(r.translation.mean, 0.1 / 3, 1e-12);
  EXPECT_NEAR(r.translation.median, 0.0, 1e-12);
  EXPECT_NEAR(r.translation.max, 0.1, 1e-12);
  EXPECT_NEAR(r.rotation.max, 0.1 * 180 / M_PI, 1e-9);
  EXPECT_NEAR(r.rotation.mean, 0.1 * 180 / M_PI / 3, 1e-9);
  RpeOptions two;
  two.delta = 2;
  r = rtabmap::computeRpe(gt, est, two);
  EXPECT_EQ(r.translation.count, 2u);  // (0,2) and (1,3)
  EXPECT_NEAR(r.translation.mean, 0.1, 1e-12);
  RpeOptions metres;
  metres.unit = RpeOptions::Unit::kMetres;
  metres.delta = 1.5;  // (0,2), (1,3): the first poses at least 1.5 m further
  r = rtabmap::computeRpe(gt, est, metres);
  EXPECT_EQ(r.translation.count, 2u);
  EXPECT_NEAR(r.translation.max, 0.1, 1e-12);
  EXPECT_NEAR(r.rotation.max, 0.1 * 180 / M_PI, 1e-9);
  metres.delta = 10.0;
  EXPECT_THROW(rtabmap::computeRpe(gt, est, metres), FormatError);
  RpeOptions fractional;
  fractional.delta = 1.5;
  EXPECT_THROW(rtabmap::computeRpe(gt, est, fractional), FormatError);
}

TEST(KittiError, DevkitSegmentsByHand) {
  // 1,000 frames 1 m apart along a straight line; the estimate 1% too long. A segment of L
  // metres starting at frame f ends at the first frame farther than L: f + L + 1, so its error
  // is 1% of L + 1 m over L: 1% * (1 + 1/L). Starts every 10 frames: for L = 100 the starts
  // 0, 10, ..., 890 (90 segments), ..., for L = 800 the starts 0..190 (20).
  std::vector<Transform> gt, est;
  for (int i = 0; i < 1000; ++i) {
    gt.push_back(Transform(i, 0, 0));
    est.push_back(Transform(1.01 * i, 0, 0));
  }
  const auto r = rtabmap::computeKittiError(gt, est);
  EXPECT_EQ(r.frames, 1000u);
  EXPECT_EQ(r.segments, 440u);
  ASSERT_EQ(r.perLength.size(), 8u);
  const size_t counts[8] = {90, 80, 70, 60, 50, 40, 30, 20};
  double sumInvLength = 0.0;
  for (size_t i = 0; i < 8; ++i) {
    const double L = 100.0 * static_cast<double>(i + 1);
    EXPECT_EQ(r.perLength[i].segments, counts[i]);
    EXPECT_NEAR(r.perLength[i].translationPercent, 1.0 * (1.0 + 1.0 / L), 1e-9);
    EXPECT_NEAR(r.perLength[i].rotationDegPerMetre, 0.0, 1e-12);
    sumInvLength += static_cast<double>(counts[i]) / L;
  }
  EXPECT_NEAR(r.translationPercent, (440.0 + sumInvLength) / 440.0, 1e-9);  // 1.0043587 %
  EXPECT_NEAR(r.translationPercent, 1.0043587, 1e-7);
  EXPECT_NEAR(r.rotationDegPerMetre, 0.0, 1e-12);

  // A constant heading error of the estimate does not change relative rotations along a
  // straight line, but bends its relative translations: |t err| = 2 (L+1) sin(a/2).
  std::vector<Transform> turned;
  const double a = 0.01;
  for (int i = 0; i < 1000; ++i) turned.push_back(Transform(i, 0, 0) * Transform(0, 0, a));
  const auto t = rtabmap::computeKittiError(gt, turned);
  EXPECT_NEAR(t.perLength[0].translationPercent, 100.0 * 2.0 * 101.0 * std::sin(a / 2) / 100.0, 1e-9);
  EXPECT_NEAR(t.rotationDegPerMetre, 0.0, 1e-12);

  std::vector<Transform> shortGt(gt.begin(), gt.begin() + 50), shortEst(est.begin(), est.begin() + 50);
  EXPECT_THROW(rtabmap::computeKittiError(shortGt, shortEst), FormatError);
  EXPECT_THROW(rtabmap::computeKittiError(gt, shortEst), FormatError);
}

TEST(KittiError, RotationDriftByHand) {
  // The estimate turns 0.001 rad per frame more than the ground truth, in place (positions
  // equal): each L-metre segment (L + 1 frames) has a rotation error of 0.001 (L + 1) rad.
  std::vector<Transform> gt, est;
  for (int i = 0; i < 300; ++i) {
    gt.push_back(Transform(i, 0, 0));
    est.push_back(Transform(i, 0, 0.001 * i));
  }
  rtabmap::KittiOptions options;
  options.lengths = {100};
  const auto r = rtabmap::computeKittiError(gt, est, options);
  EXPECT_EQ(r.segments, 20u);  // starts 0..190
  EXPECT_NEAR(r.rotationDegPerMetre, 0.001 * 101.0 / 100.0 * 180.0 / M_PI, 1e-9);
}

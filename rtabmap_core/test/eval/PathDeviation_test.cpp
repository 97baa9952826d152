// Deviation from a reference path: exact distances to the polyline, the rigid alignment, what
// it sees (a bowed corridor) and what it cannot (an error along the path).
#include "rtabmap_core/eval/PathDeviation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {
namespace {

Trajectory fromPoints(const std::vector<Eigen::Vector2d>& points, double firstStamp = 0.0) {
  Trajectory t;
  for (size_t i = 0; i < points.size(); ++i) {
    t.add(firstStamp + static_cast<double>(i), Transform{points[i].x(), points[i].y(), 0.0, 0.0, 0.0, 0.0});
  }
  return t;
}

// An L-shaped building corridor then a room: 10 m east, 6 m north, 3 m west (vertices only).
Trajectory corridorReference() {
  return fromPoints({{0, 0}, {10, 0}, {10, 6}, {7, 6}});
}

// Positions every `step` metres along the reference's polyline, `offset(s)` metres to its left
// at arc length s.
Trajectory walk(double step, const std::function<double(double)>& offset) {
  const std::vector<Eigen::Vector2d> v{{0, 0}, {10, 0}, {10, 6}, {7, 6}};
  std::vector<Eigen::Vector2d> out;
  double s0 = 0.0;
  for (size_t k = 0; k + 1 < v.size(); ++k) {
    const Eigen::Vector2d d = (v[k + 1] - v[k]).normalized();
    const Eigen::Vector2d left(-d.y(), d.x());
    const double len = (v[k + 1] - v[k]).norm();
    for (double s = 0.0; s < len - 1e-9; s += step) out.push_back(v[k] + s * d + offset(s0 + s) * left);
    s0 += len;
  }
  out.push_back(v.back());
  return fromPoints(out, 100.0);
}

TEST(PathDeviation, ExactDistancesToThePolylineWithoutAlignment) {
  PathDeviationOptions o;
  o.maxIterations = 0;  // no ICP: the distances of the positions as given
  o.initFromFirstPoses = false;
  // Across the first segment, beyond the corner (nearest: the corner itself), off the second
  // segment, and a point on the path.
  const Trajectory est = fromPoints({{5, 0.3}, {10.3, -0.4}, {9.8, 3}, {8, 6}});
  const PathDeviationResult r = computePathDeviation(corridorReference(), est, o);
  ASSERT_EQ(r.deviations.size(), 4u);
  EXPECT_NEAR(r.deviations[0], 0.3, 1e-12);
  EXPECT_NEAR(r.deviations[1], 0.5, 1e-12);
  EXPECT_NEAR(r.deviations[2], 0.2, 1e-12);
  EXPECT_NEAR(r.deviations[3], 0.0, 1e-12);
  EXPECT_EQ(r.referencePoses, 4u);
  EXPECT_NEAR(r.referenceLength, 19.0, 1e-12);
  EXPECT_NEAR(r.stats.max, 0.5, 1e-12);
}

TEST(PathDeviation, RigidlyMovedCopyIsAlignedBackToZero) {
  const Trajectory truth = walk(0.1, [](double) { return 0.0; });
  const Transform moved{3.0, -2.0, 0.0, 0.0, 0.0, 0.8};
  Trajectory est;
  for (const StampedPose& p : truth.poses) est.add(p.stamp, moved * p.pose);
  // From the first poses (the robot starts at the same place in both): exact at once.
  PathDeviationResult r = computePathDeviation(corridorReference(), est);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.stats.max, 1e-6);
  EXPECT_LT((r.alignment * moved).getNorm(), 1e-6);
  EXPECT_LT((r.alignment * moved).getAngle(), 1e-6);

  // From the identity, a small offset is found by the ICP itself.
  const Transform small{0.25, 0.15, 0.0, 0.0, 0.0, 0.04};
  Trajectory est2;
  for (const StampedPose& p : truth.poses) est2.add(p.stamp, small * p.pose);
  PathDeviationOptions o;
  o.initFromFirstPoses = false;
  r = computePathDeviation(corridorReference(), est2, o);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.stats.max, 1e-3);
  EXPECT_LT((r.alignment * small).getNorm(), 1e-3);
}

// Of the deviations of the positions walked after the first corridor (walk(0.05): its first
// 200 positions, stamps 100 to 299, are along the first 10 m), the fraction under 5 cm.
double fractionOnPathAfterTheCorner(const PathDeviationResult& r, const Trajectory& est) {
  size_t on = 0, all = 0;
  for (size_t k = 0; k < r.deviations.size(); ++k) {
    if (est[r.estimateIndices[k]].stamp < 300.0) continue;
    ++all;
    if (r.deviations[k] < 0.05) ++on;
  }
  EXPECT_GT(all, 50u);
  return all ? static_cast<double>(on) / static_cast<double>(all) : 0.0;
}

TEST(PathDeviation, BowedCorridorIsSeen) {
  // The first corridor bowed 0.3 m to the right at its middle, the rest exact: under the
  // trimming distance the fit is least squares, so the bow is shared with the rest but shows.
  const Trajectory est = walk(0.05, [](double s) { return s < 10.0 ? -0.3 * std::sin(M_PI * s / 10.0) : 0.0; });
  const PathDeviationResult r = computePathDeviation(corridorReference(), est);
  EXPECT_GT(r.stats.max, 0.15);
  EXPECT_LT(r.stats.max, 0.31);
  EXPECT_GT(r.p90, 0.1);
}

TEST(PathDeviation, GrossStretchIsTrimmedAndTheRestStaysOnThePath) {
  // 6 m of the first corridor 1.5 m off, with 0.2 m ramps (a stretch placed by a wrong loop
  // closure): left out of the fit, reported whole, and the rest of the path aligned as if it
  // were not there.
  const auto bump = [](double s) { return 1.5 * std::clamp(std::min(s - 2.0, 8.0 - s) / 0.2, 0.0, 1.0); };
  const Trajectory est = walk(0.05, bump);
  const PathDeviationResult r = computePathDeviation(corridorReference(), est);
  EXPECT_NEAR(r.stats.max, 1.5, 0.1);
  EXPECT_GT(fractionOnPathAfterTheCorner(r, est), 0.9);
  // Without trimming the bump drags the alignment off the rest of the path.
  PathDeviationOptions untrimmed;
  untrimmed.trimDistance = 1e9;
  const PathDeviationResult u = computePathDeviation(corridorReference(), est, untrimmed);
  EXPECT_LT(fractionOnPathAfterTheCorner(u, est), 0.5);
}

TEST(PathDeviation, ErrorAlongThePathIsNotSeen) {
  // Every position 0.5 m further along the first corridor: the trajectory is wrong, the shape
  // is not, and the metric (a lower bound) says 0 there.
  PathDeviationOptions o;
  o.maxIterations = 0;
  o.initFromFirstPoses = false;
  const Trajectory est = fromPoints({{0.5, 0}, {3.5, 0}, {7.5, 0}});
  const PathDeviationResult r = computePathDeviation(corridorReference(), est, o);
  EXPECT_LT(r.stats.max, 1e-12);
}

TEST(PathDeviation, NullPosesAreSkippedAndTooFewPosesAreErrors) {
  Trajectory est = walk(0.5, [](double) { return 0.0; });
  est.add(1000.0, Transform());  // a null pose: no deviation for it
  const PathDeviationResult r = computePathDeviation(corridorReference(), est);
  EXPECT_EQ(r.estimatedPoses, est.size() - 1);
  EXPECT_EQ(r.deviations.size(), est.size() - 1);
  EXPECT_THROW(computePathDeviation(fromPoints({{0, 0}}), est), FormatError);
  EXPECT_THROW(computePathDeviation(corridorReference(), fromPoints({{0, 0}, {1, 0}})), FormatError);
}

TEST(Percentile, NearestRank) {
  EXPECT_DOUBLE_EQ(percentile({5, 1, 4, 2, 3}, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(percentile({5, 1, 4, 2, 3}, 0.5), 3.0);
  EXPECT_DOUBLE_EQ(percentile({5, 1, 4, 2, 3}, 0.6), 3.0);  // round(2.4) = 2
  EXPECT_DOUBLE_EQ(percentile({5, 1, 4, 2, 3}, 0.7), 4.0);  // round(2.8) = 3
  EXPECT_DOUBLE_EQ(percentile({5, 1, 4, 2, 3}, 1.0), 5.0);
  EXPECT_DOUBLE_EQ(percentile({}, 0.5), 0.0);
}

}  // namespace
}  // namespace rtabmap

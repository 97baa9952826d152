// The tf correction with a wheel-odometry guess, the display clouds and the update rates.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rtabmap_odom/OdometryOutputs.h"

namespace rtabmap_odom {
namespace {

using rtabmap::Transform;

void expectNear(const Transform& a, const Transform& b, double tol = 1e-9) {
  ASSERT_FALSE(a.isNull());
  ASSERT_FALSE(b.isNull());
  EXPECT_TRUE(a.toEigen().matrix().isApprox(b.toEigen().matrix(), tol)) << a.prettyPrint() << " vs " << b.prettyPrint();
}

TEST(OdometryOutputs, GuessCorrectionChainsBackToTheOdometryPose) {
  const Transform odomPose(2.0, 1.0, 0.0, 0.0, 0.0, 0.7);    // base in odom (visual/lidar odometry)
  const Transform wheelPose(1.8, 1.3, 0.0, 0.0, 0.0, 0.65);  // base in the wheel odometry frame
  const Transform correction = guessFrameCorrection(odomPose, wheelPose);
  // tf composes odom -> wheel frame -> base: it must give the odometry pose.
  expectNear(correction * wheelPose, odomPose);
  // Equal poses: the frames coincide.
  expectNear(guessFrameCorrection(odomPose, odomPose), Transform::Identity());
  EXPECT_TRUE(guessFrameCorrection(Transform(), wheelPose).isNull());
}

TEST(OdometryOutputs, TwistIsTheMotionOverItsInterval) {
  const Eigen::Matrix<double, 6, 1> v = twistFromMotion(Transform(0.2, -0.1, 0.0, 0.0, 0.0, 0.05), 0.1);
  EXPECT_NEAR(v[0], 2.0, 1e-9);
  EXPECT_NEAR(v[1], -1.0, 1e-9);
  EXPECT_NEAR(v[2], 0.0, 1e-9);
  EXPECT_NEAR(v[5], 0.5, 1e-9);
  EXPECT_TRUE(twistFromMotion(Transform(), 0.1).isZero());
  EXPECT_TRUE(twistFromMotion(Transform(1.0, 0.0, 0.0), 0.0).isZero());
}

TEST(OdometryOutputs, PointsAsScanDropsPointsWithoutDepth) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const rtabmap::LaserScan scan = pointsAsScan({{1, 2, 3}, {nan, 0, 0}, {4, 5, 6}});
  ASSERT_EQ(scan.size(), 2);
  EXPECT_EQ(scan.format(), rtabmap::LaserScan::kXYZ);
  EXPECT_FLOAT_EQ(scan.point(1).x(), 4.0f);
  EXPECT_FLOAT_EQ(scan.point(1).z(), 6.0f);
  EXPECT_TRUE(pointsAsScan({{nan, nan, nan}}).empty());
}

TEST(OdometryOutputs, ScanInFrameAppliesTheMountingThenThePose) {
  cv::Mat data(1, 1, CV_32FC2);
  data.at<cv::Vec2f>(0, 0) = cv::Vec2f(1.0f, 0.0f);  // 1 m ahead of the laser
  // Laser 0.5 m ahead of the base, base at (10, 0) facing +y.
  const rtabmap::LaserScan scan(data, 1, 0.0, 30.0, rtabmap::LaserScan::kXY, Transform(0.5, 0.0, 0.0));
  const rtabmap::LaserScan placed = scanInFrame(scan, Transform(10.0, 0.0, M_PI / 2));
  ASSERT_EQ(placed.size(), 1);
  EXPECT_NEAR(placed.point(0).x(), 10.0f, 1e-5);
  EXPECT_NEAR(placed.point(0).y(), 1.5f, 1e-5);
  EXPECT_TRUE(placed.localTransform().isIdentity());
}

TEST(OdometryOutputs, UpdateRateLimiterKeepsOneFrameInTheRatePeriod) {
  UpdateRateLimiter limiter(10.0);  // 10 Hz out of a 30 Hz camera: every third frame
  int kept = 0;
  for (int i = 0; i < 30; ++i) kept += limiter.accept(100.0 + i / 30.0);
  EXPECT_EQ(kept, 10);
  // A stamp back in time (bag restarted) starts over instead of blocking until it catches up.
  EXPECT_TRUE(limiter.accept(50.0));
  UpdateRateLimiter off;
  EXPECT_TRUE(off.accept(1.0));
  EXPECT_TRUE(off.accept(1.0001));
}

TEST(OdometryOutputs, UpdateRateTooLowBelowEightyPercent) {
  EXPECT_FALSE(updateRateTooLow(45, 5.0, 10.0));
  EXPECT_TRUE(updateRateTooLow(39, 5.0, 10.0));
  EXPECT_FALSE(updateRateTooLow(0, 5.0, 0.0));  // no expectation
}

}  // namespace
}  // namespace rtabmap_odom

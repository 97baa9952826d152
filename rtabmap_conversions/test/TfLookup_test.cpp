#include "rtabmap_conversions/TfLookup.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "TestHelpers.h"

using namespace rtabmap_conversions;
using rtabmap_conversions::test::setTransform;
using rtabmap::Transform;
using Clock = std::chrono::steady_clock;

namespace {

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

TEST(TfLookup, FindsStaticAndTimedTransforms) {
  tf2::BufferCore buffer;
  const Transform laser(0.25, 0.0, 0.1, 0.0, 0.0, M_PI);
  setTransform(buffer, "base_link", "laser", laser, 0.0, true);
  setTransform(buffer, "odom", "base_link", Transform(0, 0, 0), 10.0, false);
  setTransform(buffer, "odom", "base_link", Transform(2, 0, 0), 12.0, false);
  std::string error;
  Transform t = lookupTransform(buffer, "base_link", "laser", ros::Time(11.0), 0.0, &error);
  ASSERT_FALSE(t.isNull()) << error;
  EXPECT_TRUE(t.toEigen().isApprox(laser.toEigen(), 1e-12));
  t = lookupTransform(buffer, "odom", "laser", ros::Time(11.0), 0.0, &error);  // interpolated odometry
  ASSERT_FALSE(t.isNull()) << error;
  EXPECT_NEAR(t.x(), 1.25, 1e-9);  // base at x = 1 (half way), laser 0.25 m ahead
  EXPECT_TRUE(lookupTransform(buffer, "odom", "odom", ros::Time(99.0), 0.0).isIdentity());
  t = lookupTransform(buffer, "odom", "base_link", ros::Time(0), 0.0, &error);  // latest
  ASSERT_FALSE(t.isNull()) << error;
  EXPECT_NEAR(t.x(), 2.0, 1e-12);
}

TEST(TfLookup, MotionBetweenTwoStamps) {
  tf2::BufferCore buffer;
  setTransform(buffer, "odom", "base_link", Transform(1, 1, M_PI / 2), 10.0, false);
  setTransform(buffer, "odom", "base_link", Transform(1, 2, M_PI / 2), 11.0, false);
  std::string error;
  const Transform motion = lookupMotion(buffer, "odom", "base_link", ros::Time(10.0), ros::Time(11.0), 0.0, &error);
  ASSERT_FALSE(motion.isNull()) << error;
  // Moving +y in odom while facing +y is moving forward (+x) in the robot's own frame.
  EXPECT_NEAR(motion.x(), 1.0, 1e-9);
  EXPECT_NEAR(motion.y(), 0.0, 1e-9);
  EXPECT_NEAR(motion.theta(), 0.0, 1e-9);
  EXPECT_TRUE(lookupMotion(buffer, "odom", "base_link", ros::Time(10.0), ros::Time(30.0), 0.0, &error).isNull());
  EXPECT_NE(error.find("motion of base_link in odom"), std::string::npos) << error;
}

TEST(TfLookup, MissingFramesAreNamedAndNothingThrows) {
  tf2::BufferCore buffer;
  setTransform(buffer, "base_link", "laser", Transform::Identity(), 0.0, true);
  std::string error;
  const auto start = Clock::now();
  EXPECT_TRUE(lookupTransform(buffer, "base_link", "camera_link", ros::Time(5.0), 0.1, &error).isNull());
  const double waited = secondsSince(start);
  EXPECT_GE(waited, 0.09);
  EXPECT_LT(waited, 1.0);  // bounded by the wait, whatever the ROS clock does
  EXPECT_NE(error.find("base_link <- camera_link"), std::string::npos) << error;
  EXPECT_NE(error.find("frame 'camera_link' is unknown to tf"), std::string::npos) << error;
  EXPECT_NE(error.find("wait_for_transform_duration"), std::string::npos) << error;
  EXPECT_NE(error.find("t=5.000000"), std::string::npos) << error;

  EXPECT_TRUE(lookupTransform(buffer, "", "laser", ros::Time(5.0), 0.0, &error).isNull());
  EXPECT_NE(error.find("empty"), std::string::npos) << error;

  // Known frames that are not connected: tf's own explanation is passed on.
  setTransform(buffer, "odom", "base_footprint", Transform::Identity(), 5.0, false);
  EXPECT_TRUE(lookupTransform(buffer, "laser", "base_footprint", ros::Time(5.0), 0.0, &error).isNull());
  EXPECT_NE(error.find("laser <- base_footprint"), std::string::npos) << error;
  EXPECT_GT(error.size(), 80u) << error;  // carries tf's message
}

TEST(TfLookup, ExtrapolationIsReportedWithTfsReason) {
  tf2::BufferCore buffer;
  setTransform(buffer, "odom", "base_link", Transform(0, 0, 0), 10.0, false);
  setTransform(buffer, "odom", "base_link", Transform(1, 0, 0), 11.0, false);
  std::string error;
  EXPECT_TRUE(lookupTransform(buffer, "odom", "base_link", ros::Time(20.0), 0.0, &error).isNull());
  EXPECT_NE(error.find("xtrapolation"), std::string::npos) << error;
}

TEST(TfLookup, WaitsForATransformThatArrivesLater) {
  tf2::BufferCore buffer;
  setTransform(buffer, "odom", "base_link", Transform(0, 0, 0), 10.0, false);
  std::thread publisher([&buffer] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    setTransform(buffer, "odom", "base_link", Transform(3, 0, 0), 12.0, false);
  });
  std::string error;
  const auto start = Clock::now();
  const Transform t = lookupTransform(buffer, "odom", "base_link", ros::Time(11.0), 2.0, &error);
  const double waited = secondsSince(start);
  publisher.join();
  ASSERT_FALSE(t.isNull()) << error;
  EXPECT_NEAR(t.x(), 1.5, 1e-9);
  EXPECT_GE(waited, 0.05);
  EXPECT_LT(waited, 1.5);  // returned as soon as it could, not at the end of the wait
}

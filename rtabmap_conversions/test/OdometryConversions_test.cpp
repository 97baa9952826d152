#include "rtabmap_conversions/OdometryConversions.h"

#include <gtest/gtest.h>

#include <limits>

using namespace rtabmap_conversions;
using rtabmap::Transform;

namespace {

std_msgs::Header odomHeader() {
  std_msgs::Header h;
  h.frame_id = "odom";
  h.stamp = ros::Time(1234, 500000000);
  return h;
}

Covariance6 someCovariance() {
  Covariance6 c = Covariance6::Zero();
  for (int i = 0; i < 6; ++i) c(i, i) = 0.001 * (i + 1);
  c(0, 1) = c(1, 0) = 0.0002;
  c(5, 0) = c(0, 5) = -0.0001;
  return c;
}

}  // namespace

TEST(OdometryConversions, PoseAndCovarianceRoundTrip) {
  const Transform pose(1.0, -2.0, 0.1, 0.01, -0.02, 1.2);
  const nav_msgs::Odometry msg = odometryToMsg(pose, someCovariance(), odomHeader(), "base_link");
  EXPECT_EQ(msg.header.frame_id, "odom");
  EXPECT_EQ(msg.child_frame_id, "base_link");
  EXPECT_DOUBLE_EQ(msg.pose.covariance[1], 0.0002);   // row-major: (0, 1)
  EXPECT_DOUBLE_EQ(msg.pose.covariance[30], -0.0001); // (5, 0)
  std::string error;
  const std::optional<OdometryReading> back = odometryFromMsg(msg, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_FALSE(back->lost());
  EXPECT_TRUE(back->pose.toEigen().isApprox(pose.toEigen(), 1e-12));
  EXPECT_EQ(back->covariance, someCovariance());
  EXPECT_DOUBLE_EQ(back->stamp, 1234.5);
  EXPECT_EQ(back->frameId, "odom");
  EXPECT_EQ(back->childFrameId, "base_link");
}

TEST(OdometryConversions, LostIsANullPoseWith9999Covariance) {
  const nav_msgs::Odometry msg = odometryToMsg(Transform(), someCovariance(), odomHeader(), "base_link");
  EXPECT_EQ(msg.pose.pose.orientation.w, 0.0);
  EXPECT_EQ(msg.pose.pose.orientation.x, 0.0);
  EXPECT_EQ(msg.pose.pose.position.x, 0.0);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(msg.pose.covariance[size_t(i * 7)], kLostCovariance);
  EXPECT_EQ(msg.pose.covariance[1], 0.0);
  const std::optional<OdometryReading> back = odometryFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_TRUE(back->lost());
  EXPECT_EQ(back->covariance(2, 2), kLostCovariance);
}

TEST(OdometryConversions, HugeXVarianceMeansLostButHugeZDoesNot) {
  nav_msgs::Odometry msg = odometryToMsg(Transform(1, 2, 0.5), someCovariance(), odomHeader(), "base_link");
  msg.pose.covariance[0] = 9999.0;  // a valid-looking pose flagged lost by its covariance
  std::optional<OdometryReading> back = odometryFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_TRUE(back->lost());

  msg = odometryToMsg(Transform(1, 2, 0.5), someCovariance(), odomHeader(), "base_link");
  msg.pose.covariance[14] = msg.pose.covariance[21] = msg.pose.covariance[28] = 1e6;  // planar wheel odometry
  back = odometryFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_FALSE(back->lost());
  EXPECT_NEAR(back->pose.theta(), 0.5, 1e-12);
}

TEST(OdometryConversions, TwistIsRead) {
  nav_msgs::Odometry msg = odometryToMsg(Transform::Identity(), someCovariance(), odomHeader(), "base_link");
  msg.twist.twist.linear.x = 0.5;
  msg.twist.twist.angular.z = -0.25;
  msg.twist.covariance[35] = 0.01;
  const std::optional<OdometryReading> back = odometryFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->twist(0), 0.5);
  EXPECT_EQ(back->twist(5), -0.25);
  EXPECT_EQ(back->twistCovariance(5, 5), 0.01);
}

TEST(OdometryConversions, NaNsAndMissingFramesAreErrors) {
  std::string error;
  nav_msgs::Odometry msg = odometryToMsg(Transform::Identity(), someCovariance(), odomHeader(), "base_link");
  nav_msgs::Odometry nanPose = msg;
  nanPose.pose.pose.position.y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(odometryFromMsg(nanPose, &error));
  EXPECT_NE(error.find("NaN"), std::string::npos) << error;
  nav_msgs::Odometry nanCov = msg;
  nanCov.pose.covariance[7] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(odometryFromMsg(nanCov, &error));
  nav_msgs::Odometry noFrame = msg;
  noFrame.header.frame_id.clear();
  EXPECT_FALSE(odometryFromMsg(noFrame, &error));
  EXPECT_NE(error.find("frame_id"), std::string::npos) << error;
}

TEST(OdometryConversions, CovarianceArraysAreRowMajor) {
  Covariance6 c;
  for (int r = 0; r < 6; ++r) {
    for (int k = 0; k < 6; ++k) c(r, k) = r * 10 + k;
  }
  const boost::array<double, 36> a = covarianceToMsg(c);
  EXPECT_EQ(a[8], 12.0);  // row 1, column 2
  EXPECT_EQ(covarianceFromMsg(a), c);
}

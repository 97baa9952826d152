#include "rtabmap_conversions/LandmarkConversions.h"

#include <gtest/gtest.h>

#include <limits>

using namespace rtabmap_conversions;

namespace {

rtabmap_ros::LandmarkDetection detection() {
  rtabmap_ros::LandmarkDetection d;
  d.header.frame_id = "camera_optical";
  d.header.stamp = ros::Time(5, 0);
  d.id = 4;
  d.size = 0.16f;
  d.pose.pose.position.x = 0.2;
  d.pose.pose.position.y = -0.1;
  d.pose.pose.position.z = 1.5;
  d.pose.pose.orientation.x = 1.0;  // facing the camera (180 degrees about x)
  d.pose.pose.orientation.w = 0.0;
  return d;
}

TEST(LandmarkConversions, PoseSizeAndCovariance) {
  rtabmap_ros::LandmarkDetection d = detection();
  for (int i = 0; i < 6; ++i) d.pose.covariance[i * 7] = 0.002 * (i + 1);
  std::string error;
  const std::optional<rtabmap::Landmark> l = landmarkFromMsg(d, 0.5, 0.6, &error);
  ASSERT_TRUE(l) << error;
  EXPECT_EQ(l->id, 4);
  EXPECT_FLOAT_EQ(l->size, 0.16f);
  EXPECT_NEAR(l->pose.z(), 1.5, 1e-12);
  EXPECT_NEAR(std::fabs(l->pose.roll()), M_PI, 1e-9);
  EXPECT_DOUBLE_EQ(l->covariance(0, 0), 0.002);
  EXPECT_DOUBLE_EQ(l->covariance(5, 5), 0.012);
}

TEST(LandmarkConversions, NoCovarianceTakesTheGivenVariances) {
  const std::optional<rtabmap::Landmark> l = landmarkFromMsg(detection(), 0.001, 0.01);
  ASSERT_TRUE(l);
  EXPECT_DOUBLE_EQ(l->covariance(1, 1), 0.001);
  EXPECT_DOUBLE_EQ(l->covariance(4, 4), 0.01);
  EXPECT_DOUBLE_EQ(l->covariance(0, 1), 0.0);
}

TEST(LandmarkConversions, BadDetectionsSayWhy) {
  const auto refused = [](rtabmap_ros::LandmarkDetection d, const std::string& expected) {
    std::string error;
    EXPECT_FALSE(landmarkFromMsg(d, 0.001, 0.01, &error));
    EXPECT_NE(error.find(expected), std::string::npos) << error;
  };
  rtabmap_ros::LandmarkDetection d = detection();
  d.id = 0;
  refused(d, "ids start at 1");
  d = detection();
  d.header.frame_id.clear();
  refused(d, "frame_id");
  d = detection();
  d.pose.pose.position.x = std::numeric_limits<double>::quiet_NaN();
  refused(d, "NaN or infinite pose");
  d = detection();
  d.pose.pose.orientation.x = 0.0;
  refused(d, "zero-length");
  d = detection();
  d.size = -1.0f;
  refused(d, "size");
  d = detection();
  d.pose.covariance[0] = std::numeric_limits<double>::infinity();
  refused(d, "covariance");
  d = detection();
  d.pose.covariance[0] = 0.01;  // given, but without the other variances
  refused(d, "non-positive diagonal");
}

}  // namespace

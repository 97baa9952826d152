#include "rtabmap_conversions/OdomInfoConversions.h"

#include <gtest/gtest.h>

#include <limits>

using namespace rtabmap_conversions;
using rtabmap::Transform;

namespace {

std_msgs::Header header() {
  std_msgs::Header h;
  h.frame_id = "odom";
  h.stamp = ros::Time(1700000000, 123456789);
  return h;
}

}  // namespace

TEST(OdomInfoConversions, RoundTripAndType) {
  rtabmap::OdometryInfo info;
  info.lost = false;
  info.reg.matches = 300;
  info.reg.inliers = 120;
  info.reg.icpInliersRatio = 0.75;
  info.reg.icpCorrespondences = 500;
  info.reg.icpStructuralComplexity = 0.4;
  info.reg.matchesIDs = {1, 2, 3};
  info.reg.inliersIDs = {2};
  info.features = 800;
  info.localMapSize = 1500;
  info.localScanMapSize = 9000;
  info.localKeyFrames = 5;
  info.keyFrameAdded = true;
  info.timeEstimationMs = 25.0;
  info.stamp = header().stamp.toSec();
  info.interval = 0.1;
  info.distanceTravelled = 12.5;
  info.transform = Transform(0.1, 0.0, 0.01);
  info.guess = Transform(0.09, 0.0, 0.0);
  info.covariance = Eigen::Matrix<double, 6, 6>::Identity() * 0.002;
  const rtabmap_ros::OdomInfo msg = odomInfoToMsg(info, rtabmap::Odometry::Type::kS2M, header());
  EXPECT_EQ(msg.type, 0);
  EXPECT_FLOAT_EQ(msg.timeEstimation, 0.025f);  // seconds, as the classic message
  EXPECT_EQ(odomInfoToMsg(info, rtabmap::Odometry::Type::kF2F, header()).type, 1);
  EXPECT_EQ(odomInfoToMsg(info, rtabmap::Odometry::Type::kS2S, header()).type, 1);
  std::string error;
  const std::optional<rtabmap::OdometryInfo> back = odomInfoFromMsg(msg, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_FALSE(back->lost);
  EXPECT_EQ(back->reg.matches, 300);
  EXPECT_EQ(back->reg.inliers, 120);
  EXPECT_FLOAT_EQ(float(back->reg.icpInliersRatio), 0.75f);
  EXPECT_EQ(back->reg.icpCorrespondences, 500);
  EXPECT_EQ(back->reg.matchesIDs, info.reg.matchesIDs);
  EXPECT_EQ(back->reg.inliersIDs, info.reg.inliersIDs);
  EXPECT_EQ(back->features, 800);
  EXPECT_EQ(back->localMapSize, 1500);
  EXPECT_EQ(back->localScanMapSize, 9000);
  EXPECT_EQ(back->localKeyFrames, 5);
  EXPECT_TRUE(back->keyFrameAdded);
  EXPECT_NEAR(back->timeEstimationMs, 25.0, 1e-4);
  EXPECT_DOUBLE_EQ(back->stamp, info.stamp);  // from the header: float32 cannot hold it
  EXPECT_FLOAT_EQ(float(back->distanceTravelled), 12.5f);
  EXPECT_TRUE(back->transform.toEigen().isApprox(info.transform.toEigen(), 1e-12));
  EXPECT_TRUE(back->guess.toEigen().isApprox(info.guess.toEigen(), 1e-12));
  EXPECT_EQ(back->covariance, info.covariance);
}

TEST(OdomInfoConversions, LostAndNaN) {
  rtabmap::OdometryInfo info;
  info.lost = true;
  info.covariance = Eigen::Matrix<double, 6, 6>::Identity() * 9999.0;
  rtabmap_ros::OdomInfo msg = odomInfoToMsg(info, rtabmap::Odometry::Type::kF2M, header());
  EXPECT_TRUE(msg.lost);
  EXPECT_EQ(msg.transform.rotation.w, 0.0);  // null transform
  const std::optional<rtabmap::OdometryInfo> back = odomInfoFromMsg(msg);
  ASSERT_TRUE(back);
  EXPECT_TRUE(back->lost);
  EXPECT_TRUE(back->transform.isNull());
  msg.covariance[0] = std::numeric_limits<double>::quiet_NaN();
  std::string error;
  EXPECT_FALSE(odomInfoFromMsg(msg, &error));
  EXPECT_NE(error.find("covariance"), std::string::npos) << error;
}

// Frame-to-frame visual odometry: descriptor matching and optical flow.
#include <gtest/gtest.h>

#include "odometry/VisualOdometryTestUtil.h"
#include "rtabmap_core/odometry/OdometryF2F.h"

namespace rtabmap {
namespace {

TEST(OdometryF2F, FollowsWithDescriptorMatching) {
  OdometryF2F odom;
  const test::OdometryRun run = test::runOdometry(odom, 60, test::rgbdFrame);
  EXPECT_EQ(run.lost, 0);
  EXPECT_LT(run.maxError, 0.045);
  EXPECT_GT(odom.keyFramesAdded(), 1);
  EXPECT_FALSE(odom.keyFramePose().isNull());
}

TEST(OdometryF2F, FollowsWithOpticalFlow) {
  OdometryF2F odom(ParametersMap{{"Vis/CorType", "1"}});
  const test::OdometryRun run = test::runOdometry(odom, 60, test::rgbdFrame);
  EXPECT_EQ(run.lost, 0);
  EXPECT_LT(run.maxError, 0.04);
}

TEST(OdometryF2F, FollowsAStereoSequence) {
  OdometryF2F odom(ParametersMap{{"Vis/CorType", "1"}});
  const test::OdometryRun run = test::runOdometry(odom, 60, test::stereoFrame);
  EXPECT_EQ(run.lost, 0);
  EXPECT_LT(run.maxError, 0.07);
}

TEST(OdometryF2F, LostOnBlankFramesThenRecovers) {
  OdometryF2F odom(ParametersMap{{"Vis/CorType", "1"}});
  const auto frame = [](int i) {
    SensorData data = test::rgbdFrame(i);
    if (i == 15) data.setRGBDImage(cv::Mat::zeros(data.imageRaw().size(), CV_8UC3), data.depthOrRightRaw(), data.cameraModels());
    return data;
  };
  const test::OdometryRun run = test::runOdometry(odom, 30, frame);
  EXPECT_EQ(run.lost, 1);
  EXPECT_TRUE(run.poses[15].isNull());
  EXPECT_FALSE(run.poses[16].isNull());
  EXPECT_LT(run.maxError, 0.04);
}

}  // namespace
}  // namespace rtabmap

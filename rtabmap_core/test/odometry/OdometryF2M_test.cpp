// Frame-to-map visual odometry on rendered RGB-D and stereo sequences with known poses.
#include <gtest/gtest.h>

#include "odometry/VisualOdometryTestUtil.h"
#include "rtabmap_core/odometry/OdometryF2M.h"

namespace rtabmap {
namespace {

using test::rgbdFrame;
using test::runOdometry;
using test::stereoFrame;

constexpr int kFrames = 60;

TEST(OdometryF2M, FollowsAnRgbdSequence) {
  OdometryF2M odom;
  const test::OdometryRun run = runOdometry(odom, kFrames, rgbdFrame);
  EXPECT_EQ(run.lost, 0);
  EXPECT_LT(run.maxError, 0.045);
  EXPECT_GT(odom.keyFramesAdded(), 1);
  EXPECT_LT(odom.keyFramesAdded(), kFrames / 2);  // not every frame
  EXPECT_GT(odom.localMapSize(), 200);
  EXPECT_LE(odom.localMapSize(), 2000);
  EXPECT_TRUE(run.infos[0].keyFrameAdded);
  for (size_t i = 1; i < run.infos.size(); ++i) {
    const OdometryInfo& info = run.infos[i];
    EXPECT_FALSE(info.lost);
    EXPECT_GT(info.features, 100);
    EXPECT_GE(info.reg.inliers, 20);
    EXPECT_LT(info.covariance(0, 0), 0.01);
    EXPECT_EQ(info.localMapSize, info.keyFrameAdded || i > 0 ? info.localMapSize : 0);
  }
  // The frames were given their features and odometry pose.
  SensorData last = rgbdFrame(kFrames);
  EXPECT_FALSE(odom.process(last).isNull());
  EXPECT_FALSE(last.keypoints().empty());
  EXPECT_FALSE(last.odomPose().isNull());
}

TEST(OdometryF2M, FollowsAStereoSequence) {
  OdometryF2M odom;
  const test::OdometryRun run = runOdometry(odom, kFrames, stereoFrame);
  EXPECT_EQ(run.lost, 0);
  EXPECT_LT(run.maxError, 0.06);
}

TEST(OdometryF2M, LocalBundleAdjustment) {
  OdometryF2M odom(ParametersMap{{"OdomF2M/BundleAdjustment", "3"}});
  const test::OdometryRun run = runOdometry(odom, kFrames, rgbdFrame);
  EXPECT_EQ(run.lost, 0);
  EXPECT_LT(run.maxError, 0.045);
}

TEST(OdometryF2M, MapStaysUnderMaxSize) {
  OdometryF2M odom(ParametersMap{{"OdomF2M/MaxSize", "300"}, {"Odom/KeyFrameThr", "0.6"}});
  for (int i = 0; i < 30; ++i) {
    SensorData data = rgbdFrame(i);
    OdometryInfo info;
    EXPECT_FALSE(odom.process(data, &info).isNull()) << info.lostReason;
    EXPECT_LE(info.localMapSize, 300);
    EXPECT_LE(odom.localMapSize(), 300);
  }
  EXPECT_EQ(odom.localMapPoints().size(), static_cast<size_t>(odom.localMapSize()));
}

TEST(OdometryF2M, LostOnBlankFramesThenRecovers) {
  OdometryF2M odom;
  const auto frame = [](int i) {
    SensorData data = rgbdFrame(i);
    if (i >= 20 && i < 23) {
      data.setRGBDImage(cv::Mat::zeros(data.imageRaw().size(), CV_8UC3), data.depthOrRightRaw(), data.cameraModels());
    }
    return data;
  };
  const test::OdometryRun run = runOdometry(odom, 40, frame);
  EXPECT_EQ(run.lost, 3);
  for (int i = 20; i < 23; ++i) {
    const OdometryInfo& info = run.infos[static_cast<size_t>(i)];
    EXPECT_TRUE(run.poses[static_cast<size_t>(i)].isNull());
    EXPECT_TRUE(info.lost);
    EXPECT_NE(info.lostReason.find("no features"), std::string::npos) << info.lostReason;
    EXPECT_DOUBLE_EQ(info.covariance(0, 0), 9999.0);
    EXPECT_DOUBLE_EQ(info.covariance(5, 5), 9999.0);
  }
  // Recovered on the next frame, against the map kept while lost, without prediction.
  EXPECT_FALSE(run.poses[23].isNull());
  EXPECT_FALSE(run.infos[23].lost);
  EXPECT_TRUE(run.infos[23].guess.isNull());
  EXPECT_LT(run.maxError, 0.045);
  EXPECT_EQ(odom.lostCount(), 0);
}

TEST(OdometryF2M, ResetCountdownRestartsTheMap) {
  OdometryF2M odom(ParametersMap{{"Odom/ResetCountdown", "2"}});
  const auto frame = [](int i) {
    SensorData data = rgbdFrame(i);
    if (i >= 10 && i < 13) {
      data.setRGBDImage(cv::Mat::zeros(data.imageRaw().size(), CV_8UC3), data.depthOrRightRaw(), data.cameraModels());
    }
    return data;
  };
  const test::OdometryRun run = runOdometry(odom, 20, frame);
  EXPECT_FALSE(run.infos[10].autoReset);
  EXPECT_TRUE(run.infos[11].autoReset);
  // Frame 12 (blank) cannot start the new map; frame 13 does, at the last pose before the loss.
  EXPECT_TRUE(run.poses[12].isNull());
  ASSERT_FALSE(run.poses[13].isNull());
  EXPECT_TRUE(run.infos[13].keyFrameAdded);
  EXPECT_LT(run.poses[13].getDistance(run.poses[9]), 1e-9);
  for (int i = 14; i < 20; ++i) EXPECT_FALSE(run.poses[static_cast<size_t>(i)].isNull());
}

}  // namespace
}  // namespace rtabmap

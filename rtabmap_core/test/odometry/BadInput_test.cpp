// Bad sensor data never crashes visual odometry: each kind is a lost frame with its reason,
// and odometry recovers when good data returns.
#include <gtest/gtest.h>

#include <functional>
#include <limits>

#include "odometry/VisualOdometryTestUtil.h"
#include "rtabmap_core/odometry/OdometryF2F.h"
#include "rtabmap_core/odometry/OdometryF2M.h"

namespace rtabmap {
namespace {

struct BadCase {
  const char* name;
  std::function<SensorData(const SensorData&)> corrupt;
  const char* reason;  // expected in the lost reason
};

std::vector<BadCase> badCases() {
  return {
      {"no texture",
       [](const SensorData& d) {
         SensorData out = d;
         out.setRGBDImage(cv::Mat(d.imageRaw().size(), CV_8UC3, cv::Scalar(120, 120, 120)), d.depthOrRightRaw(),
                          d.cameraModels());
         return out;
       },
       "no features"},
      {"all-NaN depth",
       [](const SensorData& d) {
         SensorData out = d;
         out.setRGBDImage(d.imageRaw(),
                          cv::Mat(d.imageRaw().size(), CV_32FC1, cv::Scalar(std::numeric_limits<float>::quiet_NaN())),
                          d.cameraModels());
         return out;
       },
       "no valid pixel"},
      {"all-zero depth",
       [](const SensorData& d) {
         SensorData out = d;
         out.setRGBDImage(d.imageRaw(), cv::Mat::zeros(d.imageRaw().size(), CV_16UC1), d.cameraModels());
         return out;
       },
       "no valid pixel"},
      {"zero focal length",
       [](const SensorData& d) {
         SensorData out = d;
         out.setRGBDImage(d.imageRaw(), d.depthOrRightRaw(), {CameraModel(0.0, 0.0, 160, 120)});
         return out;
       },
       "not valid for projection"},
      {"mismatched RGB and depth sizes",
       [](const SensorData& d) {
         SensorData out = d;
         out.setRGBDImage(d.imageRaw(), cv::Mat(200, 150, CV_32FC1, cv::Scalar(2.0f)), d.cameraModels());
         return out;
       },
       "does not match"},
      {"no depth at all",
       [](const SensorData& d) {
         SensorData out = d;
         out.setRGBDImage(d.imageRaw(), cv::Mat(), d.cameraModels());
         return out;
       },
       "no depth image"},
      {"no image", [](const SensorData&) { return SensorData(); }, "no image"},
  };
}

template <typename Approach>
void checkBadInput(const ParametersMap& parameters) {
  for (const BadCase& bad : badCases()) {
    SCOPED_TRACE(bad.name);
    Approach odom(parameters);
    const auto frame = [&](int i) {
      const SensorData good = test::rgbdFrame(i);
      return (i == 8 || i == 9) ? bad.corrupt(good) : good;
    };
    test::OdometryRun run;
    EXPECT_NO_THROW(run = test::runOdometry(odom, 14, frame));
    EXPECT_EQ(run.lost, 2);
    for (int i : {8, 9}) {
      EXPECT_TRUE(run.poses[static_cast<size_t>(i)].isNull());
      EXPECT_NE(run.infos[static_cast<size_t>(i)].lostReason.find(bad.reason), std::string::npos)
          << run.infos[static_cast<size_t>(i)].lostReason;
    }
    EXPECT_FALSE(run.poses[10].isNull()) << run.infos[10].lostReason;
    EXPECT_LT(run.maxError, 0.03);
  }
}

TEST(BadInput, F2MRecoversFromEveryKind) { checkBadInput<OdometryF2M>({}); }

TEST(BadInput, F2FRecoversFromEveryKind) { checkBadInput<OdometryF2F>({{"Vis/CorType", "1"}}); }

TEST(BadInput, BadFirstFrameDoesNotStartTheMap) {
  OdometryF2M odom;
  SensorData flat = test::rgbdFrame(0);
  flat.setRGBDImage(cv::Mat(flat.imageRaw().size(), CV_8UC3, cv::Scalar(50, 50, 50)), flat.depthOrRightRaw(),
                    flat.cameraModels());
  OdometryInfo info;
  EXPECT_TRUE(odom.process(flat, &info).isNull());
  EXPECT_TRUE(info.lost);
  EXPECT_EQ(odom.localMapSize(), 0);
  SensorData good = test::rgbdFrame(0);
  EXPECT_TRUE(odom.process(good, &info).isIdentity());
  EXPECT_GT(odom.localMapSize(), 100);
}

TEST(BadInput, StereoWithoutBaseline) {
  OdometryF2M odom;
  SensorData bad = test::stereoFrame(0);
  const CameraModel& left = bad.stereoCameraModels()[0].left();
  bad.setStereoImage(bad.imageRaw(), bad.depthOrRightRaw(),
                     StereoCameraModel(left.fx(), left.fy(), left.cx(), left.cy(), 0.0));
  OdometryInfo info;
  EXPECT_TRUE(odom.process(bad, &info).isNull());
  EXPECT_NE(info.lostReason.find("stereo camera model not valid"), std::string::npos) << info.lostReason;
  SensorData good = test::stereoFrame(0);
  EXPECT_FALSE(odom.process(good, &info).isNull());
}

}  // namespace
}  // namespace rtabmap

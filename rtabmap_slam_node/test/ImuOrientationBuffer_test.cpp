#include "rtabmap_slam_node/ImuOrientationBuffer.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rtabmap_slam_node {
namespace {

Eigen::Quaterniond pitch(double a) { return Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY())); }

ImuOrientation sample(double stamp, double pitchRad, const std::string& frame = "imu_link") {
  return {stamp, pitch(pitchRad), frame};
}

TEST(ImuOrientationBuffer, OrientationAtAFrameStampIsInterpolated) {
  ImuOrientationBuffer b(5.0, 0.1);
  EXPECT_FALSE(b.at(10.0)) << "nothing received yet";
  for (int i = 0; i <= 10; ++i) ASSERT_TRUE(b.add(sample(10.0 + 0.01 * i, 0.1 * i)));
  const std::optional<ImuOrientation> mid = b.at(10.025);
  ASSERT_TRUE(mid);
  EXPECT_NEAR(mid->orientation.angularDistance(pitch(0.25)), 0.0, 1e-9);
  EXPECT_EQ(mid->frameId, "imu_link");
  EXPECT_DOUBLE_EQ(mid->stamp, 10.025);
  ASSERT_TRUE(b.at(10.05));
  EXPECT_NEAR(b.at(10.05)->orientation.angularDistance(pitch(0.5)), 0.0, 1e-9);
  // Just past the newest sample: held; farther: unknown. Before the history: unknown.
  ASSERT_TRUE(b.at(10.15));
  EXPECT_NEAR(b.at(10.15)->orientation.angularDistance(pitch(1.0)), 0.0, 1e-9);
  EXPECT_FALSE(b.at(10.3));
  EXPECT_FALSE(b.at(9.99));
}

TEST(ImuOrientationBuffer, BadOrOutOfOrderSamplesAreRefusedWithAReason) {
  ImuOrientationBuffer b;
  std::string why;
  EXPECT_FALSE(b.add({1.0, Eigen::Quaterniond(0, 0, 0, 0), "imu"}, &why));
  EXPECT_NE(why.find("no orientation"), std::string::npos) << why;
  EXPECT_FALSE(b.add({1.0, Eigen::Quaterniond(NAN, 0, 0, 1), "imu"}, &why));
  EXPECT_NE(why.find("finite"), std::string::npos) << why;
  ASSERT_TRUE(b.add(sample(2.0, 0.0)));
  EXPECT_FALSE(b.add(sample(1.5, 0.0), &why));
  EXPECT_NE(why.find("not after"), std::string::npos) << why;
  // A non-unit quaternion is normalised.
  ASSERT_TRUE(b.add({2.01, Eigen::Quaterniond(2, 0, 0, 0), "imu_link"}, &why));
  EXPECT_NEAR(b.at(2.01)->orientation.norm(), 1.0, 1e-12);
}

TEST(ImuOrientationBuffer, GapsHistoryAndClockJumps) {
  ImuOrientationBuffer b(1.0, 0.1);
  ASSERT_TRUE(b.add(sample(1.0, 0.0)));
  ASSERT_TRUE(b.add(sample(1.5, 0.5)));  // the IMU stopped for 0.5 s
  EXPECT_FALSE(b.at(1.25)) << "no interpolation across a gap";
  for (int i = 1; i <= 30; ++i) ASSERT_TRUE(b.add(sample(1.5 + 0.05 * i, 0.5)));
  EXPECT_FALSE(b.at(1.2)) << "older than the second kept";
  EXPECT_TRUE(b.at(2.9));
  EXPECT_TRUE(b.add(sample(0.5, 0.2))) << "older than the history kept: time went back, the history goes";
  EXPECT_FALSE(b.at(2.9));
  EXPECT_TRUE(b.at(0.5));
  b.clear();
  EXPECT_TRUE(b.empty());
  EXPECT_TRUE(b.add(sample(0.4, 0.0))) << "after a clear, older stamps are accepted again";
}

TEST(ImuOrientationBuffer, NoInterpolationBetweenTwoImus) {
  ImuOrientationBuffer b;
  ASSERT_TRUE(b.add(sample(1.0, 0.0, "imu_a")));
  ASSERT_TRUE(b.add(sample(1.01, 0.3, "imu_b")));
  EXPECT_FALSE(b.at(1.005));
}

}  // namespace
}  // namespace rtabmap_slam_node

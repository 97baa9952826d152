#include "rtabmap_conversions/ImuOrientationBuffer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace rtabmap_conversions {
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

sensor_msgs::Imu message(double stamp, const Eigen::Quaterniond& q, bool withOrientation = true) {
  sensor_msgs::Imu m;
  m.header.stamp.fromSec(stamp);
  m.header.frame_id = "imu_link";
  m.orientation.x = q.x();
  m.orientation.y = q.y();
  m.orientation.z = q.z();
  m.orientation.w = q.w();
  if (!withOrientation) m.orientation_covariance[0] = -1.0;  // sensor_msgs/Imu: no orientation
  return m;
}

// The topic's messages: an orientation is kept, a raw IMU's message is told apart from a bad one.
TEST(ImuOrientationBuffer, MessagesAreKeptOrToldWhyNot) {
  using Intake = ImuOrientationBuffer::Intake;
  ImuOrientationBuffer b;
  std::string why;
  EXPECT_EQ(b.add(message(1.0, pitch(0.1)), &why), Intake::kKept) << why;
  EXPECT_EQ(b.add(message(1.01, pitch(0.1), false), &why), Intake::kNoOrientation);
  EXPECT_NE(why.find("raw IMU"), std::string::npos) << why;
  EXPECT_EQ(b.add(message(1.0, pitch(0.2)), &why), Intake::kRefused) << "not after the previous sample";
  sensor_msgs::Imu bad = message(1.02, pitch(0.1));
  bad.orientation.x = std::nan("");
  EXPECT_EQ(b.add(bad, &why), Intake::kRefused);
  EXPECT_FALSE(why.empty());
  ASSERT_TRUE(b.at(1.0));
  EXPECT_NEAR(b.at(1.0)->orientation.angularDistance(pitch(0.1)), 0.0, 1e-9);
}

// What a frame carries: the orientation at its stamp with the IMU's pose on the robot, or why not.
TEST(ImuOrientationBuffer, AFrameGetsTheImuAtItsStampWithItsMount) {
  ImuOrientationBuffer b;
  ASSERT_TRUE(b.add(sample(1.0, 0.0)));
  ASSERT_TRUE(b.add(sample(1.05, 0.2)));
  const rtabmap::Transform mount(0.1, 0.0, 0.2, M_PI, 0.0, 0.0);
  std::vector<std::string> asked;
  auto localOf = [&](const std::string& frame, std::string* why) {
    asked.push_back(frame);
    if (frame == "imu_link") return mount;
    if (why) *why = "no tf for " + frame;
    return rtabmap::Transform();
  };
  std::string why;
  const std::optional<rtabmap::IMU> imu = b.imuAt(1.025, localOf, &why);
  ASSERT_TRUE(imu) << why;
  EXPECT_NEAR(imu->orientation.angularDistance(pitch(0.1)), 0.0, 1e-9);
  EXPECT_EQ(imu->localTransform, mount);
  EXPECT_EQ(asked, std::vector<std::string>{"imu_link"});

  EXPECT_FALSE(b.imuAt(3.0, localOf, &why)) << "no sample near";
  EXPECT_NE(why.find("no imu orientation"), std::string::npos) << why;
  ImuOrientationBuffer other;
  ASSERT_TRUE(other.add(sample(1.0, 0.0, "imu_unknown")));
  EXPECT_FALSE(other.imuAt(1.0, localOf, &why)) << "no tf for the IMU's frame";
  EXPECT_EQ(why, "no tf for imu_unknown");
}

// The mounting is asked of tf once and kept; a frame tf does not know yet is asked again only
// after a second (each lookup may wait for tf).
TEST(ImuOrientationBuffer, TheMountIsLookedUpOnceAndFailuresAreNotRetriedAtEverySample) {
  ImuOrientationBuffer b;
  ASSERT_TRUE(b.add(sample(1.0, 0.0)));
  ASSERT_TRUE(b.add(sample(1.05, 0.0)));
  int asked = 0;
  bool known = false;
  const rtabmap::Transform mount(0.1, 0.0, 0.2, M_PI, 0.0, 0.0);
  auto localOf = [&](const std::string&, std::string* why) {
    ++asked;
    if (known) return mount;
    if (why) *why = "no tf yet";
    return rtabmap::Transform();
  };
  std::string why;
  EXPECT_FALSE(b.imuAt(1.0, localOf, &why));
  EXPECT_EQ(why, "no tf yet");
  known = true;
  EXPECT_FALSE(b.imuAt(1.01, localOf, &why)) << "not asked again within a second";
  EXPECT_NE(why.find("imu_link"), std::string::npos) << why;
  EXPECT_EQ(asked, 1);
  EXPECT_FALSE(b.mountOf("imu_other", localOf).isNull());
  EXPECT_EQ(asked, 2) << "another frame is asked at once";
  EXPECT_EQ(b.mountOf("imu_other", localOf), mount);
  EXPECT_EQ(asked, 2) << "kept once found";
}

}  // namespace
}  // namespace rtabmap_conversions

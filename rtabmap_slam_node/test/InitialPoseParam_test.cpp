#include "rtabmap_slam_node/InitialPoseParam.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rtabmap_slam_node {
namespace {

TEST(InitialPoseParam, EmptyMeansNoPose) {
  std::string why = "stale";
  EXPECT_FALSE(parseInitialPose("", &why));
  EXPECT_TRUE(why.empty());
  EXPECT_FALSE(parseInitialPose("   ", &why));
  EXPECT_TRUE(why.empty());
}

TEST(InitialPoseParam, SixValuesAreXYZRollPitchYaw) {
  std::string why;
  const std::optional<rtabmap::Transform> t = parseInitialPose("1.5 -2 0.1 0 0 1.2", &why);
  ASSERT_TRUE(t) << why;
  EXPECT_NEAR(t->x(), 1.5, 1e-9);
  EXPECT_NEAR(t->y(), -2.0, 1e-9);
  EXPECT_NEAR(t->z(), 0.1, 1e-9);
  EXPECT_NEAR(t->theta(), 1.2, 1e-6);
  // Commas too, and a roll / pitch that are not zero come back.
  const std::optional<rtabmap::Transform> r = parseInitialPose("0,0,0, 0.1,-0.2,0.3", &why);
  ASSERT_TRUE(r) << why;
  EXPECT_NEAR((r->inverse() * rtabmap::Transform(0, 0, 0, 0.1, -0.2, 0.3)).getAngle(), 0.0, 1e-6);
}

TEST(InitialPoseParam, SevenValuesAreXYZAndAQuaternionNormalised) {
  std::string why;
  // Yaw 90 degrees, the quaternion scaled by 2.
  const std::optional<rtabmap::Transform> t = parseInitialPose("3 4 0 0 0 1.41421356 1.41421356", &why);
  ASSERT_TRUE(t) << why;
  EXPECT_NEAR(t->x(), 3.0, 1e-9);
  EXPECT_NEAR(t->theta(), M_PI / 2, 1e-6);
}

TEST(InitialPoseParam, BadTextIsRefusedWithAReason) {
  std::string why;
  EXPECT_FALSE(parseInitialPose("1 2 3", &why));
  EXPECT_NE(why.find("3 values"), std::string::npos) << why;
  EXPECT_FALSE(parseInitialPose("1 2 3 4 5 six", &why));
  EXPECT_NE(why.find("\"six\""), std::string::npos) << why;
  EXPECT_FALSE(parseInitialPose("1 2 3 4 5 nan", &why));
  EXPECT_NE(why.find("finite"), std::string::npos) << why;
  EXPECT_FALSE(parseInitialPose("1 2 3 0 0 0 0", &why));
  EXPECT_NE(why.find("zero"), std::string::npos) << why;
  EXPECT_FALSE(parseInitialPose("1 2 3 4 5 6e", &why));
}

}  // namespace
}  // namespace rtabmap_slam_node

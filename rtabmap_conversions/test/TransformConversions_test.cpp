#include "rtabmap_conversions/TransformConversions.h"

#include <gtest/gtest.h>

using rtabmap::Transform;
using namespace rtabmap_conversions;

TEST(TransformConversions, RoundTripThroughTransformAndPose) {
  const Transform t(1.0, -2.0, 0.5, 0.1, -0.2, 2.5);
  const Transform back = transformFromMsg(transformToMsg(t));
  EXPECT_TRUE(back.toEigen().isApprox(t.toEigen(), 1e-12));
  const Transform backPose = transformFromPoseMsg(transformToPoseMsg(t));
  EXPECT_TRUE(backPose.toEigen().isApprox(t.toEigen(), 1e-12));
  const geometry_msgs::Transform msg = transformToMsg(t);
  EXPECT_DOUBLE_EQ(msg.translation.y, -2.0);
}

TEST(TransformConversions, NullTravelsAsZeroQuaternion) {
  const geometry_msgs::Transform msg = transformToMsg(Transform());
  EXPECT_EQ(msg.rotation.w, 0.0);
  EXPECT_TRUE(transformFromMsg(msg).isNull());
  geometry_msgs::Pose nanPose;
  nanPose.orientation.w = 1.0;
  nanPose.position.x = std::nan("");
  EXPECT_TRUE(transformFromPoseMsg(nanPose).isNull());
}

TEST(TransformConversions, DenormalisedQuaternionIsNormalised) {
  geometry_msgs::Transform msg;
  msg.rotation.z = 0.5;
  msg.rotation.w = 0.5;  // norm 0.707: a 90 degree yaw once normalised
  EXPECT_NEAR(transformFromMsg(msg).yaw(), M_PI / 2.0, 1e-12);
}

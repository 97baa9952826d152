// The registration of the SLAM links (LinkRegistration.h): Reg/RepeatOnce, a visual transform
// found without a guess registered again from itself.
#include <gtest/gtest.h>

#include "../../src/slam/LinkRegistration.h"
#include "odometry/SyntheticRoom.h"
#include "rtabmap_core/memory/Signature.h"

namespace rtabmap {
namespace {

using test::SyntheticRoom;

const Transform kFrom(0.0, 0.2, 1.1, 0.0, 0.0, 0.3);
const Transform kMotion(0.12, -0.05, 0.02, 0.01, 0.03, 0.08);  // from -> to

Transform registerPair(bool repeatOnce, const Transform& guess, RegistrationInfo* info) {
  static const SyntheticRoom room;
  const CameraModel m = SyntheticRoom::camera();
  Signature a(room.rgbd(kFrom, m, 1)), b(room.rgbd(kFrom * kMotion, m, 2));
  const LinkRegistration registration(ParametersMap{{"Reg/RepeatOnce", repeatOnce ? "true" : "false"}});
  return registration.compute(a, b, guess, info);
}

TEST(LinkRegistration, WithoutAGuessTheVisualTransformIsRegisteredAgainFromItself) {
  RegistrationInfo once, repeated, fromFirst;
  const Transform first = registerPair(false, Transform(), &once);
  ASSERT_FALSE(first.isNull()) << once.rejectedMsg;
  const Transform again = registerPair(true, Transform(), &repeated);
  const Transform guided = registerPair(false, first, &fromFirst);
  ASSERT_FALSE(again.isNull()) << repeated.rejectedMsg;
  // The repeated registration is the one from the first estimate, its matches included.
  EXPECT_LT(again.getDistance(guided), 1e-9);
  EXPECT_EQ(repeated.matches, fromFirst.matches);
  EXPECT_EQ(repeated.inliers, fromFirst.inliers);
  EXPECT_NE(repeated.matches, once.matches) << "guided matching found the same correspondences as descriptors alone";
  EXPECT_LT(again.getDistance(kMotion), 0.015);
}

TEST(LinkRegistration, WithAGuessItRegistersOnce) {
  const Transform guess = kMotion * Transform(0.02, 0.01, 0, 0, 0, 0.01);
  RegistrationInfo a, b;
  const Transform repeatOn = registerPair(true, guess, &a);
  const Transform repeatOff = registerPair(false, guess, &b);
  ASSERT_FALSE(repeatOn.isNull());
  EXPECT_LT(repeatOn.getDistance(repeatOff), 1e-9);
  EXPECT_EQ(a.matches, b.matches);
}

}  // namespace
}  // namespace rtabmap

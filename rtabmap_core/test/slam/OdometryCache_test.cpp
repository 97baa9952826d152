// Localization mode's odometry cache: a localization is applied only when a second one at a
// later frame agrees with it through odometry, a link that disagrees with the recent ones is
// refused, and a loop closure outweighs the proximity links it contradicts.
#include "../../src/slam/OdometryCache.h"

#include <gtest/gtest.h>

namespace rtabmap {
namespace {

// The robot drives along x in its odometry frame, one metre a frame; map -> odom is kTruth.
const Transform kTruth(10.0, 5.0, 0.3);
constexpr int kNodeBase = 100;  // map node n sits 1.5 m ahead of frame n, 0.5 m to its left

Link::InfMatrix information(double linearStd, double angularStd) {
  Link::InfMatrix inf = Link::InfMatrix::Zero();
  for (int i = 0; i < 3; ++i) inf(i, i) = 1.0 / (linearStd * linearStd);
  for (int i = 3; i < 6; ++i) inf(i, i) = 1.0 / (angularStd * angularStd);
  return inf;
}

Transform odomOf(int frame) { return Transform(static_cast<double>(frame), 0.0, 0.0); }

OdometryCacheOptions twoD(int maxSize = 10) {
  OdometryCacheOptions o;
  o.maxSize = maxSize;
  o.maxErrorRatio = 3.0;
  o.optimizer.force3DoF = true;
  return o;
}

// A localization of frame `frame` on map node kNodeBase + frame, measured as if the robot were
// `offset` (in the map frame) away from where it really is.
CachedLink localization(int frame, const Transform& offset = Transform::Identity(),
                        Link::Type type = Link::kLocalSpaceClosure) {
  const Transform robot = kTruth * odomOf(frame);
  const Transform node = robot * Transform(1.5, 0.5, 0.1);
  const Transform believed = offset * robot;
  return {Link(0, kNodeBase + frame, type, believed.inverse() * node, information(0.05, 0.02)), node};
}

void addFrame(OdometryCache& cache, int frame) { cache.addFrame(odomOf(frame), information(0.02, 0.01)); }

TEST(OdometryCache, FirstLocalizationWaitsForASecondThatAgrees) {
  OdometryCache cache(twoD());
  addFrame(cache, 0);
  const OdometryCacheVerdict first = cache.verify(localization(0));
  EXPECT_TRUE(first.accepted);
  EXPECT_FALSE(first.confirmed) << "one link alone is not a localization";
  EXPECT_NE(first.why.find("confirm"), std::string::npos) << first.why;

  addFrame(cache, 1);
  const OdometryCacheVerdict second = cache.verify(localization(1));
  ASSERT_TRUE(second.accepted) << second.why;
  EXPECT_TRUE(second.confirmed);
  EXPECT_LT(second.worstRatio, 0.01);
  const Transform expected = kTruth * odomOf(1);
  EXPECT_LT(second.pose.getDistance(expected), 1e-3) << second.pose.prettyPrint();
  EXPECT_NEAR((second.pose.inverse() * expected).theta(), 0.0, 1e-4);
  EXPECT_EQ(cache.links(), 2u);
}

TEST(OdometryCache, ALinkThatDisagreesWithTheRecentOnesIsRefusedAndNotKept) {
  OdometryCache cache(twoD());
  for (int f = 0; f < 2; ++f) {
    addFrame(cache, f);
    ASSERT_TRUE(cache.verify(localization(f)).accepted);
  }
  addFrame(cache, 2);
  // Matched on a look-alike 2 m to the side: the odometry since the last two cannot hold it.
  const OdometryCacheVerdict wrong = cache.verify(localization(2, Transform(0.0, 2.0, 0.0)));
  EXPECT_FALSE(wrong.accepted);
  EXPECT_FALSE(wrong.confirmed);
  EXPECT_GT(wrong.worstRatio, 3.0);
  EXPECT_NE(wrong.why.find("RGBD/OptimizeMaxError"), std::string::npos) << wrong.why;
  EXPECT_EQ(cache.links(), 2u) << "a refused link is not cached";

  addFrame(cache, 3);
  const OdometryCacheVerdict right = cache.verify(localization(3));
  EXPECT_TRUE(right.accepted) << right.why;
  EXPECT_TRUE(right.confirmed);
}

TEST(OdometryCache, SmallNoiseIsSmoothedNotRefused) {
  OdometryCache cache(twoD());
  for (int f = 0; f < 3; ++f) {
    addFrame(cache, f);
    ASSERT_TRUE(cache.verify(localization(f)).accepted);
  }
  addFrame(cache, 3);
  // 6 cm off (about one standard deviation of a link): kept, and the pose lands between what
  // this link says alone and the truth the earlier links and odometry agree on.
  const Transform offset(0.06, 0.0, 0.0);
  const OdometryCacheVerdict v = cache.verify(localization(3, offset));
  ASSERT_TRUE(v.accepted) << v.why;
  EXPECT_TRUE(v.confirmed);
  const Transform truth = kTruth * odomOf(3);
  const Transform alone = offset * truth;
  EXPECT_LT(v.pose.getDistance(truth), alone.getDistance(truth));
  EXPECT_GT(v.pose.getDistance(truth), 0.001);
}

TEST(OdometryCache, AWrongFirstLocalizationLeavesWithItsFrame) {
  OdometryCache cache(twoD(3));
  addFrame(cache, 0);
  // The robot assumed 16 m from where it is: proximity matched a look-alike there.
  ASSERT_TRUE(cache.verify(localization(0, Transform(16.0, 0.0, 0.0))).accepted);
  for (int f = 1; f < 3; ++f) {
    addFrame(cache, f);
    const OdometryCacheVerdict v = cache.verify(localization(f));
    EXPECT_FALSE(v.accepted) << "frame " << f << ": the wrong link is still cached";
  }
  // Frame 0 leaves the cache (three frames kept): the right links start over.
  addFrame(cache, 3);
  const OdometryCacheVerdict first = cache.verify(localization(3));
  EXPECT_TRUE(first.accepted) << first.why;
  EXPECT_FALSE(first.confirmed);
  addFrame(cache, 4);
  const OdometryCacheVerdict second = cache.verify(localization(4));
  EXPECT_TRUE(second.confirmed) << second.why;
  EXPECT_LT(second.pose.getDistance(kTruth * odomOf(4)), 1e-3);
}

TEST(OdometryCache, ALoopClosureOutweighsTheProximityLinksItContradicts) {
  // A loop closure, or a marker seen again (kLandmark: to the map node that saw it).
  for (Link::Type type : {Link::kGlobalClosure, Link::kLandmark}) {
    SCOPED_TRACE(Link::typeName(type));
    OdometryCache cache(twoD());
    const Transform lookAlike(0.0, 3.0, 0.0);
    for (int f = 0; f < 2; ++f) {
      addFrame(cache, f);
      ASSERT_TRUE(cache.verify(localization(f, lookAlike)).accepted);
    }
    addFrame(cache, 2);
    const OdometryCacheVerdict closure = cache.verify(localization(2, Transform::Identity(), type));
    EXPECT_TRUE(closure.accepted) << closure.why;
    EXPECT_EQ(closure.proximityDropped, 2);
    EXPECT_FALSE(closure.confirmed) << "nothing left to confirm it";
    EXPECT_EQ(cache.links(), 1u);
    // A proximity link that agrees with it now confirms it.
    addFrame(cache, 3);
    EXPECT_TRUE(cache.verify(localization(3)).confirmed);
  }
}

TEST(OdometryCache, WithoutACacheEveryLocalizationIsAppliedAtOnce) {
  for (const auto& [size, ratio] : {std::pair<int, double>{0, 3.0}, {10, 0.0}}) {
    OdometryCacheOptions o = twoD(size);
    o.maxErrorRatio = ratio;
    OdometryCache cache(o);
    addFrame(cache, 0);
    const CachedLink l = localization(0, Transform(0.0, 2.0, 0.0));
    const OdometryCacheVerdict v = cache.verify(l);
    EXPECT_TRUE(v.accepted && v.confirmed);
    EXPECT_LT(v.pose.getDistance(l.mapPose * l.link.transform().inverse()), 1e-9);
    EXPECT_EQ(cache.frames(), 0u);
  }
}

TEST(OdometryCache, KeepsAtMostItsSizeOfFrames) {
  OdometryCache cache(twoD(4));
  for (int f = 0; f < 9; ++f) addFrame(cache, f);
  EXPECT_EQ(cache.frames(), 4u);
  cache.clear();
  EXPECT_EQ(cache.frames(), 0u);
  OdometryCacheVerdict v = cache.verify(localization(0));
  EXPECT_FALSE(v.accepted);
  EXPECT_FALSE(v.why.empty());
}

}  // namespace
}  // namespace rtabmap

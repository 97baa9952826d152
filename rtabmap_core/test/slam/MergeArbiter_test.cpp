// The vote on a merge between maps: agreeing refused closures outvote a wrong first link,
// scattered ones (aliasing) do not, and the correction puts the map where they say.
#include "../../src/slam/MergeArbiter.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rtabmap {
namespace {

// The current map was merged 12 m off along x: a node the graph has at (x, 0) really is at
// (x + 12, 0), and a true closure from it says so (up to `noise` metres).
void trueDissent(MergeArbiter& arbiter, int from, double x, double noise = 0.0) {
  const Transform graphPose(x, 0.0, 0.0);
  const Transform implied(x + 12.0 + noise, noise, 0.02);
  arbiter.dissent(Link(from, 1000 + from, Link::kGlobalClosure, Transform::Identity()), graphPose, implied);
}

TEST(MergeArbiter, AgreeingRefusedClosuresOutvoteAWrongFirstLink) {
  MergeArbiter arbiter;
  arbiter.support();  // the wrong first link
  trueDissent(arbiter, 100, 0.0);
  EXPECT_FALSE(arbiter.decide(100));
  trueDissent(arbiter, 103, 2.0, 0.3);
  EXPECT_FALSE(arbiter.decide(103)) << "two are not enough (minDissent 3)";
  trueDissent(arbiter, 107, 5.0, -0.2);
  const std::optional<Remerge> r = arbiter.decide(107);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->links.size(), 3u);
  // The newest closure's correction (12.2 - 0.2 along x) when it has the most votes (a tie).
  const Transform moved = r->correction * Transform(5.0, 0.0, 0.0);
  EXPECT_NEAR(moved.x(), 5.0 + 12.0 - 0.2, 1e-9);
  EXPECT_NEAR(moved.y(), -0.2, 1e-9);
}

TEST(MergeArbiter, AWellSupportedMergeIsNotUndoneByAFewRefusals) {
  MergeArbiter arbiter;
  for (int i = 0; i < 4; ++i) arbiter.support();
  for (int i = 0; i < 4; ++i) trueDissent(arbiter, 100 + i, i);
  EXPECT_FALSE(arbiter.decide(103)) << "4 against 4: the merge stays";
  trueDissent(arbiter, 104, 4.0);
  EXPECT_TRUE(arbiter.decide(104)) << "5 against 4";
}

TEST(MergeArbiter, ScatteredAliasesDoNotAgree) {
  MergeArbiter arbiter;
  // Each refused closure puts the robot somewhere else: aliasing, not a wrong merge.
  for (int i = 0; i < 6; ++i) {
    const Transform graphPose(i, 0.0, 0.0);
    const Transform implied(i + 4.0 * (i + 1), (i % 2 ? 3.0 : -3.0) * i, 0.3 * i);
    arbiter.dissent(Link(100 + i, 10 + i, Link::kGlobalClosure, Transform::Identity()), graphPose, implied);
  }
  EXPECT_EQ(arbiter.dissentCount(), 6u);
  EXPECT_FALSE(arbiter.decide(105));
}

TEST(MergeArbiter, AgreementNeedsTheHeadingToo) {
  MergeArbiterOptions o;
  MergeArbiter arbiter(o);
  for (int i = 0; i < 3; ++i) {
    // Same position, heading 0.5 rad apart each time: more than agreementRadians.
    arbiter.dissent(Link(100 + i, 10, Link::kGlobalClosure, Transform::Identity()), Transform(0, 0, 0),
                    Transform(12.0, 0.0, 0.5 * i));
  }
  EXPECT_FALSE(arbiter.decide(102));
}

TEST(MergeArbiter, OldDissentIsForgotten) {
  MergeArbiterOptions o;
  o.windowNodes = 10;
  MergeArbiter arbiter(o);
  trueDissent(arbiter, 100, 0.0);
  trueDissent(arbiter, 101, 1.0);
  trueDissent(arbiter, 130, 3.0);
  EXPECT_FALSE(arbiter.decide(130));
  EXPECT_EQ(arbiter.dissentCount(), 1u) << "the two from more than 10 nodes ago are gone";
}

TEST(MergeArbiter, AUserLinkSettlesTheMerge) {
  MergeArbiter arbiter;
  arbiter.settle();
  for (int i = 0; i < 5; ++i) trueDissent(arbiter, 100 + i, i);
  EXPECT_FALSE(arbiter.decide(104));
  arbiter.reset();
  for (int i = 0; i < 3; ++i) trueDissent(arbiter, 200 + i, i);
  EXPECT_TRUE(arbiter.decide(202)) << "reset: a new map is put to the vote again";
}

TEST(MergeArbiter, PlanarCorrectionsKeepTheRobotOnTheFloor) {
  MergeArbiterOptions o;
  o.planar = true;
  MergeArbiter arbiter(o);
  for (int i = 0; i < 3; ++i) {
    arbiter.dissent(Link(100 + i, 10 + i, Link::kGlobalClosure, Transform::Identity()), Transform(i, 0, 0),
                    Transform(i + 12.0, 0.0, 0.3, 0.05, -0.04, 0.1));
  }
  const std::optional<Remerge> r = arbiter.decide(102);
  ASSERT_TRUE(r);
  EXPECT_NEAR(r->correction.z(), 0.0, 1e-12);
  EXPECT_NEAR(r->correction.roll(), 0.0, 1e-12);
  EXPECT_NEAR(r->correction.pitch(), 0.0, 1e-12);
  EXPECT_NEAR(r->correction.yaw(), 0.1, 1e-9);
}

TEST(MergeArbiter, InvalidOptionsAreRefused) {
  std::string why;
  MergeArbiterOptions o;
  EXPECT_TRUE(o.IsValid(&why));
  o.minDissent = 0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("minDissent"), std::string::npos);
  o = MergeArbiterOptions();
  o.agreementMetres = std::nan("");
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_THROW(MergeArbiter{o}, std::invalid_argument);
}

}  // namespace
}  // namespace rtabmap

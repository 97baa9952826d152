#include "rtabmap_core/slam/SessionGraph.h"

#include <gtest/gtest.h>

namespace rtabmap {
namespace {

TEST(SessionGraph, MapsMergeTransitivelyIntoTheOldestReferential) {
  SessionGraph g;
  g.setPose(1, 0, Transform(1, 0, 0, 0, 0, 0));
  g.setPose(2, 1, Transform(2, 0, 0, 0, 0, 0));
  g.setPose(3, 2, Transform(3, 0, 0, 0, 0, 0));
  g.setPose(4, 3, Transform());  // known, no pose yet
  EXPECT_FALSE(g.sameGroup(0, 2));
  EXPECT_EQ(g.posesOfGroup(2).size(), 1u);
  g.mergeMaps(2, 1);
  EXPECT_EQ(g.groupOf(2), 1);
  g.mergeMaps(1, 0);
  EXPECT_TRUE(g.sameGroup(0, 2));
  EXPECT_EQ(g.groupOf(2), 0) << "the oldest map represents the group";
  EXPECT_EQ(g.mapsMergedWith(2), (std::set<int>{0, 1, 2}));
  EXPECT_EQ(g.posesOfGroup(2).size(), 3u);
  EXPECT_EQ(g.posesOfGroup(3).size(), 0u) << "map 3 is its own referential and node 4 has no pose";
  EXPECT_EQ(g.mapOf(4), 3);
  EXPECT_EQ(g.mapOf(99), -1);
  EXPECT_TRUE(g.pose(99).isNull());
}

TEST(SessionGraph, MapsPartWhenTheLastLinkJoiningThemIsRemoved) {
  SessionGraph g;
  for (int m = 0; m < 4; ++m) g.setPose(m + 1, m, Transform::Identity());
  g.mergeMaps(0, 1);
  g.mergeMaps(1, 2);
  g.mergeMaps(1, 2);  // two links between maps 1 and 2
  g.mergeMaps(3, 3);  // a link within a map joins nothing
  EXPECT_EQ(g.mapsMergedWith(2), (std::set<int>{0, 1, 2}));
  g.unmergeMaps(2, 1);
  EXPECT_TRUE(g.sameGroup(0, 2)) << "one link still joins maps 1 and 2";
  g.unmergeMaps(1, 2);
  EXPECT_FALSE(g.sameGroup(0, 2));
  EXPECT_TRUE(g.sameGroup(0, 1)) << "the other groups are rebuilt as their links say";
  EXPECT_EQ(g.groupOf(2), 2);
  EXPECT_EQ(g.posesOfGroup(2).size(), 1u);
  g.unmergeMaps(2, 3);  // never joined: nothing
  g.unmergeMaps(0, 1);
  EXPECT_EQ(g.mapsMergedWith(1), (std::set<int>{1}));
  EXPECT_EQ(g.mapsMergedWith(3), (std::set<int>{3}));
}

TEST(SessionGraph, UpdatesMoveOnlyKnownNodes) {
  SessionGraph g;
  g.setPose(1, 0, Transform::Identity());
  g.updatePoses({{1, Transform(5, 0, 0, 0, 0, 0)}, {7, Transform(1, 1, 0, 0, 0, 0)}});
  EXPECT_DOUBLE_EQ(g.pose(1).x(), 5.0);
  EXPECT_FALSE(g.contains(7));
  g.erase(1);
  EXPECT_EQ(g.size(), 0u);
}

}  // namespace
}  // namespace rtabmap

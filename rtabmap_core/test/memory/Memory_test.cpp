#include "rtabmap_core/memory/Memory.h"

#include <gtest/gtest.h>

#include "MemoryTestPlaces.h"
#include "common/TestData.h"
#include "rtabmap_core/db/Database.h"

namespace rtabmap::memory {
namespace {

using test::view;

MemoryOptions smallStm(int stm = 2) {
  MemoryOptions o;
  o.stmSize = stm;
  return o;
}

TEST(Memory, NewLocationsGoThroughStmToWm) {
  Memory m(smallStm(2));
  for (int p = 1; p <= 5; ++p) {
    AddResult r = m.addLocation(view(p));
    EXPECT_EQ(r.id, p);
    EXPECT_FALSE(r.merged);
    EXPECT_EQ(r.newWords, 100);
  }
  EXPECT_EQ(m.stm(), (std::set<int>{4, 5}));
  ASSERT_EQ(m.wm().size(), 3u);
  EXPECT_TRUE(m.wm().count(1) && m.wm().count(3));
  EXPECT_EQ(m.vocabulary().size(), 500u);
  // Consecutive locations are linked (neighbours in time).
  EXPECT_TRUE(m.signature(4)->hasLink(5, Link::kNeighbor));
  EXPECT_EQ(m.neighbors(3, 1), (std::map<int, int>{{2, 1}, {3, 0}, {4, 1}}));
}

TEST(Memory, RehearsalMergesTheSamePlaceAndIncreasesTheWeight) {
  Memory m(smallStm(5));
  m.addLocation(view(1));
  m.addLocation(view(2));
  AddResult again = m.addLocation(view(2, 1));  // the robot did not move
  EXPECT_TRUE(again.merged);
  EXPECT_EQ(again.id, 2);          // the previous location keeps its id
  EXPECT_EQ(again.mergedWith, 3);
  EXPECT_GT(again.rehearsalSimilarity, 0.9f);
  EXPECT_EQ(m.signature(2)->weight(), 1);
  EXPECT_EQ(m.signature(3), nullptr);
  m.addLocation(view(2, 2));
  EXPECT_EQ(m.signature(2)->weight(), 2);
  EXPECT_EQ(m.vocabulary().size(), 200u);  // no word of the merged views stays behind
  AddResult next = m.addLocation(view(3));
  EXPECT_EQ(next.id, 5);
  EXPECT_TRUE(m.signature(2)->hasLink(5, Link::kNeighbor));
}

TEST(Memory, NoRehearsalAcrossMaps) {
  Memory m(smallStm(5));
  m.addLocation(view(1));
  LocationInput again = view(1, 1);
  again.mapId = 1;  // a new session starts where the previous one ended
  AddResult r = m.addLocation(again);
  EXPECT_FALSE(r.merged);
  EXPECT_FALSE(m.signature(1)->hasLink(r.id));
}

TEST(Memory, RehearsalCanKeepTheNewId) {
  MemoryOptions o = smallStm(5);
  o.rehearsalIdUpdatedToNewOne = true;
  Memory m(o);
  m.addLocation(view(1));
  m.addLocation(view(2));
  AddResult again = m.addLocation(view(2, 1));
  EXPECT_EQ(again.id, 3);
  EXPECT_EQ(m.signature(2), nullptr);
  EXPECT_EQ(m.signature(3)->weight(), 1);
  EXPECT_TRUE(m.signature(3)->hasLink(1, Link::kNeighbor));  // took over 2's link to 1
  EXPECT_TRUE(m.signature(1)->hasLink(3, Link::kNeighbor));
}

TEST(Memory, BadSignaturesAreFlaggedOrDropped) {
  Memory m(smallStm(0));
  m.addLocation(view(1, 0, 100));
  m.addLocation(view(2, 0, 100));
  AddResult few = m.addLocation(view(3, 0, 20));  // 20 < 0.5 x 100
  EXPECT_TRUE(few.badSignature);
  EXPECT_TRUE(m.signature(few.id)->isBadSignature());
  // Bad signatures are not loop-closure candidates.
  EXPECT_EQ(m.computeLikelihood(1).count(few.id), 0u);

  MemoryOptions o = smallStm(0);
  o.badSignaturesIgnored = true;
  Memory ignoring(o);
  ignoring.addLocation(view(1));
  AddResult dropped = ignoring.addLocation(view(3, 0, 20));
  EXPECT_EQ(dropped.id, 0);
  EXPECT_EQ(ignoring.vocabulary().size(), 100u);
  EXPECT_EQ(ignoring.addLocation(view(4)).id, 2);
}

TEST(Memory, MaxFeaturesKeepsTheStrongest) {
  MemoryOptions o = smallStm(1);
  o.maxFeatures = 30;
  Memory m(o);
  LocationInput in = view(1);
  for (size_t i = 0; i < in.keypoints.size(); ++i) in.keypoints[i].response = static_cast<float>(i);
  AddResult r = m.addLocation(in);
  EXPECT_EQ(r.words, 30);
  for (const auto& kp : m.signature(r.id)->getWordsKpts()) EXPECT_GE(kp.response, 70.f);
}

TEST(Memory, LikelihoodPeaksOnTheRevisitedPlace) {
  Memory m(smallStm(1));
  for (int p = 1; p <= 10; ++p) m.addLocation(view(p));
  AddResult r = m.addLocation(view(4, 1));
  auto l = m.computeLikelihood(r.id);
  EXPECT_EQ(l.size(), 10u);  // WM: 1..10 (the new location is in STM)
  for (const auto& [id, s] : l) {
    if (id == 4) {
      EXPECT_GT(s, 0.5f);
    } else {
      EXPECT_FLOAT_EQ(s, 0.f);
    }
  }
}

TEST(Memory, LoopClosureMovesTheWeightToTheNewerLocation) {
  Memory m(smallStm(1));
  m.addLocation(view(1));
  m.addLocation(view(1, 1));  // merged: weight 1
  m.addLocation(view(2));
  m.addLocation(view(3));
  ASSERT_EQ(m.signature(1)->weight(), 1);
  m.addLoopClosure(Link(4, 1, Link::kGlobalClosure, Transform::Identity()));
  EXPECT_EQ(m.signature(4)->weight(), 1);
  EXPECT_EQ(m.signature(1)->weight(), 0);
  EXPECT_TRUE(m.signature(1)->hasLink(4, Link::kGlobalClosure));
  EXPECT_EQ(m.summary().lastGlobalLoopClosureId, 4);
}

TEST(Memory, OptionsFromParameters) {
  MemoryOptions o = MemoryOptions::fromParameters({{"Mem/STMSize", "3"}, {"Bayes/PredictionLC", "0.1 0.5 0.4"}});
  EXPECT_EQ(o.stmSize, 3);
  EXPECT_EQ(o.neighborhoodDepth, 1);
  EXPECT_EQ(MemoryOptions::fromParameters({}).neighborhoodDepth, 16);
}

}  // namespace
}  // namespace rtabmap::memory

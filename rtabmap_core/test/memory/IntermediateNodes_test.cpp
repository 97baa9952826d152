// Intermediate nodes (Rtabmap/CreateIntermediateNodes) in memory management: poses of the
// trajectory between two locations, weight -1, no words. They chain the neighbour links but are
// no locations: STM, WM sizes, the Bayes filter's neighbourhood, the likelihood, transfer and
// retrieval see through them.
#include <gtest/gtest.h>

#include "MemoryTestPlaces.h"
#include "common/TestData.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/Memory.h"

namespace rtabmap::memory {
namespace {

using test::view;
using test::WithLtm;

LocationInput intermediate() {
  LocationInput in = view(99);  // words it must not get
  in.intermediate = true;
  return in;
}

// Locations (R) and intermediate nodes (i), ids in order: R1 i2 i3 R4 i5 R6.
void addChain(Memory& m) {
  m.addLocation(view(1));
  m.addLocation(intermediate());
  m.addLocation(intermediate());
  m.addLocation(view(2));
  m.addLocation(intermediate());
  m.addLocation(view(3));
}

TEST(IntermediateNodes, HaveNoWordsAndWeightMinusOneAndChainTheNeighbourLinks) {
  MemoryOptions o;
  o.stmSize = 10;
  Memory m(o);
  m.addLocation(view(1));
  const AddResult r = m.addLocation(intermediate());
  EXPECT_EQ(r.id, 2);
  EXPECT_TRUE(r.badSignature);
  EXPECT_EQ(r.words, 0);
  const Signature* s = m.signature(2);
  ASSERT_NE(s, nullptr);
  EXPECT_TRUE(s->isIntermediate());
  EXPECT_EQ(s->weight(), -1);
  EXPECT_TRUE(s->getWords().empty());
  EXPECT_EQ(m.vocabulary().size(), 100u);  // place 99's words never entered
  EXPECT_TRUE(m.isIntermediate(2));
  EXPECT_FALSE(m.isIntermediate(1));
  const AddResult next = m.addLocation(view(2));
  EXPECT_TRUE(m.signature(1)->hasLink(2, Link::kNeighbor));
  EXPECT_TRUE(m.signature(2)->hasLink(next.id, Link::kNeighbor));
  EXPECT_FALSE(m.signature(1)->hasLink(next.id, Link::kNeighbor));
  // The last one taken back (the robot did not move) leaves no id behind.
  m.addLocation(intermediate());
  EXPECT_TRUE(m.isIntermediate(4));
  m.removeLastLocation();
  EXPECT_FALSE(m.isIntermediate(4));
  EXPECT_EQ(m.intermediatesInRam(), 1);
}

TEST(IntermediateNodes, StmAndWmCountOnlyLocations) {
  MemoryOptions o;
  o.stmSize = 2;
  Memory m(o);
  addChain(m);  // 3 locations: R1 leaves STM; the intermediate nodes before R4 wait with it
  EXPECT_EQ(m.stm(), (std::set<int>{2, 3, 4, 5, 6}));
  EXPECT_EQ(m.wm().size(), 1u);
  m.addLocation(intermediate());  // 7
  EXPECT_EQ(m.stm().size(), 6u);
  m.addLocation(view(4));  // 8: R4 leaves, right after the intermediate nodes before it
  EXPECT_EQ(m.stm(), (std::set<int>{5, 6, 7, 8}));
  EXPECT_EQ(m.wm().size(), 4u);
  EXPECT_EQ(m.wmLocations(), 2);
  const MemorySummary s = m.summary();
  EXPECT_EQ(s.wmSize, 2);
  EXPECT_EQ(s.stmSize, 2);
  EXPECT_EQ(s.intermediatesInRam, 4);
}

TEST(IntermediateNodes, NeighbourhoodIsOfLocationsWhateverLiesBetween) {
  MemoryOptions o;
  o.stmSize = 10;
  Memory m(o);
  addChain(m);
  EXPECT_EQ(m.neighbors(4, 1), (std::map<int, int>{{1, 1}, {4, 0}, {6, 1}}));
  EXPECT_EQ(m.neighbors(1, 2), (std::map<int, int>{{1, 0}, {4, 1}, {6, 2}}));
}

// The likelihood is over locations; its TF-IDF counts locations only, so the scores are those
// of the same map without intermediate nodes.
TEST(IntermediateNodes, LikelihoodIsTheSameAsWithoutThem) {
  MemoryOptions o;
  o.stmSize = 0;
  Memory with(o), without(o);
  std::map<int, int> idOf;  // id in `with` -> id in `without`
  for (int p = 1; p <= 6; ++p) {
    const int a = with.addLocation(view(p, 0, 100, 20)).id;
    idOf[a] = without.addLocation(view(p, 0, 100, 20)).id;
    with.addLocation(intermediate());
    with.addLocation(intermediate());
  }
  const int qa = with.addLocation(view(3, 1, 100, 20)).id;
  const int qb = without.addLocation(view(3, 1, 100, 20)).id;
  const std::map<int, float> la = with.computeLikelihood(qa), lb = without.computeLikelihood(qb);
  ASSERT_EQ(la.size(), lb.size());
  for (const auto& [id, score] : la) {
    EXPECT_FALSE(with.isIntermediate(id)) << id;
    ASSERT_TRUE(idOf.count(id)) << id;
    EXPECT_FLOAT_EQ(score, lb.at(idOf.at(id))) << id;
  }
  EXPECT_GT(la.at(7), 0.f);  // place 3
}

TEST(IntermediateNodes, LeaveWmWithTheLocationAfterThem) {
  WithLtm ltm;
  MemoryOptions o;
  o.stmSize = 1;
  o.recentWmRatio = 0.f;
  Memory m(o, &ltm.database);
  addChain(m);
  m.addLocation(view(4));  // 7; WM: R1 i2 i3 R4 i5 R6
  ASSERT_EQ(m.wmLocations(), 3);
  // Down to one location: R1, then R4 with the intermediate nodes before it (newest first).
  const TransferResult r = m.transfer({}, 0, 1, false);
  EXPECT_EQ(r.transferred, (std::vector<int>{1, 4, 3, 2}));
  EXPECT_EQ(m.wmLocations(), 1);
  EXPECT_TRUE(m.inRam(5) && m.inRam(6));  // i5 goes with R6
  EXPECT_EQ(m.summary().transferredTotal, 2);
  m.joinLtmWriter();
  // Saved when they left STM, as any node (i5 too).
  EXPECT_EQ(ltm.database.intermediateNodeIds(), (std::vector<int>{2, 3, 5}));
  ASSERT_TRUE(ltm.database.loadNode(2).has_value());
  EXPECT_EQ(ltm.database.loadNode(2)->weight(), -1);
}

TEST(IntermediateNodes, RetrievalPassesThroughThemAndBringsThemBack) {
  WithLtm ltm;
  MemoryOptions o;
  o.stmSize = 1;
  o.recentWmRatio = 0.f;
  o.maxRetrieved = 2;
  Memory m(o, &ltm.database);
  // R1 i i R4 i i R7 i i R10 i i R13, then R14 in STM.
  for (int p = 1; p <= 5; ++p) {
    m.addLocation(view(p));
    if (p < 5) {
      m.addLocation(intermediate());
      m.addLocation(intermediate());
    }
  }
  m.addLocation(view(6));
  ASSERT_EQ(m.lastLocationId(), 14);
  // Everything but R7 (the hypothesis, with the intermediate nodes before it) and the STM.
  m.transfer({7}, 100000, 0, false);
  ASSERT_FALSE(m.inRam(4));
  ASSERT_TRUE(m.inRam(6));
  ASSERT_FALSE(m.inRam(8));
  // From R7: its neighbours in time are R4 and R10, two intermediate nodes away each.
  EXPECT_EQ(m.retrieve(7), (std::vector<int>{4, 10}));
  for (int i : {5, 6, 8, 9}) EXPECT_TRUE(m.inRam(i) && m.isIntermediate(i)) << i;
  EXPECT_EQ(m.neighbors(7, 1), (std::map<int, int>{{4, 1}, {7, 0}, {10, 1}}));
  EXPECT_EQ(m.summary().retrievedTotal, 2);
  // A new memory on the same database knows which of its nodes are intermediate.
  m.saveAll();
  Memory next(o, &ltm.database);
  EXPECT_TRUE(next.isIntermediate(2));
  EXPECT_TRUE(next.isIntermediate(12));
  EXPECT_FALSE(next.isIntermediate(13));
}

}  // namespace
}  // namespace rtabmap::memory

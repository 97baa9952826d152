// Graph reduction (Mem/ReduceGraph): a location that closed a loop with an older one is merged
// into it when it leaves STM; the older one takes its neighbours (composed links) and weight.
#include <gtest/gtest.h>

#include <cmath>

#include "MemoryTestPlaces.h"
#include "common/TestData.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/Memory.h"

namespace rtabmap::memory {
namespace {

using test::viewAt;
using test::WithLtm;

MemoryOptions reducing(bool reduce = true) {
  MemoryOptions o;
  o.stmSize = 2;
  o.reduceGraph = reduce;
  return o;
}

Link::InfMatrix information(double translation, double rotation) {
  Link::InfMatrix m = Link::InfMatrix::Zero();
  m.diagonal() << translation, translation, translation, rotation, rotation, rotation;
  return m;
}

// Along a corridor and back to the start: R1 (place 1, x 0; the robot waited there, so a
// second view was rehearsed into it: weight 1), R3 (x 1), R4 (x 2), then R5 sees place 1
// again where odometry, drifted by 0.1 m, says x 0.1, turned back. The loop closure R5 -> R1
// says they are the same position. Returns R5's id.
int outAndBack(Memory& m, Link::Type closure = Link::kGlobalClosure) {
  m.addLocation(viewAt(1, 0, Transform(0, 0, 0, 0, 0, 0)));
  EXPECT_TRUE(m.addLocation(viewAt(1, 2, Transform(0, 0, 0, 0, 0, 0))).merged);
  m.addLocation(viewAt(2, 0, Transform(1, 0, 0, 0, 0, 0)));
  m.addLocation(viewAt(3, 0, Transform(2, 0, 0, 0, 0, 0)));
  const int revisit = m.addLocation(viewAt(1, 1, Transform(0.1, 0, 0, 0, 0, M_PI))).id;
  const Link loop(revisit, 1, closure, Transform(0, 0, 0, 0, 0, M_PI), information(100, 400));
  if (closure == Link::kGlobalClosure) {
    m.addLoopClosure(loop);
  } else {
    m.addLink(loop);
  }
  return revisit;
}

bool same(const Transform& a, const Transform& b) {
  const Transform d = a.inverse() * b;
  return d.getNorm() < 1e-9 && std::fabs(d.getAngle()) < 1e-9;
}

// Two more locations after the revisit push it out of STM (Mem/STMSize 2).
AddResult goOn(Memory& m) {
  m.addLocation(viewAt(4, 0, Transform(-0.9, 0, 0, 0, 0, M_PI)));
  return m.addLocation(viewAt(5, 0, Transform(-1.9, 0, 0, 0, 0, M_PI)));
}

TEST(ReduceGraph, ALocationThatClosedALoopMergesIntoTheOlderOneWhenItLeavesStm) {
  Memory m(reducing());
  const int revisit = outAndBack(m);
  ASSERT_EQ(revisit, 5);
  EXPECT_EQ(m.signature(1)->weight(), 0);  // the loop closure moved the place's weight...
  EXPECT_EQ(m.signature(revisit)->weight(), 1);  // ... to the newer location
  m.addLocation(viewAt(4, 0, Transform(-0.9, 0, 0, 0, 0, M_PI)));  // R6; R4 leaves STM
  ASSERT_TRUE(m.inRam(revisit));
  const AddResult r = m.addLocation(viewAt(5, 0, Transform(-1.9, 0, 0, 0, 0, M_PI)));  // R7; R5 leaves
  EXPECT_EQ(r.reduced, (std::vector<std::pair<int, int>>{{revisit, 1}}));
  EXPECT_FALSE(m.inRam(revisit));
  EXPECT_FALSE(m.wm().count(revisit));
  EXPECT_EQ(m.summary().reducedTotal, 1);
  EXPECT_EQ(m.signature(1)->weight(), 1);  // and back: the place lives on in R1
  // No location keeps a link to it; R1 now leads to R4 and R6 through R5's links: the loop
  // closure puts R5 on R1 (turned), so R4 is where odometry saw it from R5, 1.9 m ahead of R1,
  // and R6 1 m behind, facing back.
  for (int id : {1, 3, 4, 6, 7}) EXPECT_FALSE(m.signature(id)->hasLink(revisit)) << id;
  const Link* toR4 = m.signature(1)->link(4, Link::kNeighborMerged);
  const Link* toR6 = m.signature(1)->link(6, Link::kNeighborMerged);
  ASSERT_NE(toR4, nullptr);
  ASSERT_NE(toR6, nullptr);
  EXPECT_TRUE(same(toR4->transform(), Transform(1.9, 0, 0, 0, 0, 0))) << toR4->transform().prettyPrint();
  EXPECT_TRUE(same(toR6->transform(), Transform(-1.0, 0, 0, 0, 0, M_PI))) << toR6->transform().prettyPrint();
  ASSERT_NE(m.signature(6)->link(1, Link::kNeighborMerged), nullptr);  // both ends
  ASSERT_NE(m.signature(4)->link(1, Link::kNeighborMerged), nullptr);
  // The noise of both links: less sure than the odometry alone.
  EXPECT_LT(toR6->infMatrix()(0, 0), m.signature(6)->link(7, Link::kNeighbor)->infMatrix()(0, 0));
  // The Bayes filter's neighbourhood goes through R1 now: R6 is one link from R1.
  EXPECT_EQ(m.neighbors(6, 1).count(1), 1u);
  // Its words were R1's (the same place): the vocabulary keeps the five places' words.
  EXPECT_EQ(m.vocabulary().size(), 500u);
  EXPECT_EQ(m.computeLikelihood(r.id).count(revisit), 0u);
}

TEST(ReduceGraph, OffOrForLocationsThatMustStayTheyJoinWmAsBefore) {
  {
    Memory m(reducing(false));
    const int revisit = outAndBack(m);
    EXPECT_TRUE(goOn(m).reduced.empty());
    EXPECT_TRUE(m.wm().count(revisit));
  }
  {
    Memory m(reducing());
    const int revisit = outAndBack(m);
    ASSERT_TRUE(m.setLabel(revisit, "dock"));  // a goal by name
    EXPECT_TRUE(goOn(m).reduced.empty());
    EXPECT_TRUE(m.wm().count(revisit));
  }
  {
    Memory m(reducing());
    const int revisit = outAndBack(m);
    m.addLink(Link(revisit, revisit, Link::kPosePrior, Transform::Identity()));  // GPS: absolute
    EXPECT_TRUE(goOn(m).reduced.empty());
  }
  {
    Memory m(reducing());
    const int revisit = outAndBack(m);
    LocationInput between = viewAt(9, 0, Transform(-0.4, 0, 0, 0, 0, M_PI));
    between.intermediate = true;  // Rtabmap/CreateIntermediateNodes: the trajectory stays whole
    m.addLocation(between);
    EXPECT_TRUE(goOn(m).reduced.empty());
    EXPECT_TRUE(m.wm().count(revisit));
  }
  {
    Memory m(reducing());
    // Proximity in time links views of one traversal: no revisit.
    const int revisit = outAndBack(m, Link::kLocalTimeClosure);
    EXPECT_TRUE(goOn(m).reduced.empty());
    EXPECT_TRUE(m.wm().count(revisit));
  }
  {
    Memory m(reducing());
    // A proximity link in space is a revisit too, with the record of the scans it was matched
    // against (RGBD/ScanMatchingIdsSavedInLinks) or not...
    const int revisit = outAndBack(m, Link::kLocalSpaceClosure);
    Link recorded = *m.signature(revisit)->link(1, Link::kLocalSpaceClosure);
    recorded.setUserData(Link::scanIdsUserData({1, 3}));
    m.addLink(recorded);
    EXPECT_EQ(goOn(m).reduced, (std::vector<std::pair<int, int>>{{revisit, 1}}));
  }
  {
    Memory m(reducing());
    // ... but a link with a user's data stays.
    const int revisit = outAndBack(m, Link::kUserClosure);
    Link withData = *m.signature(revisit)->link(1, Link::kUserClosure);
    withData.setUserData(cv::Mat(1, 4, CV_8UC1, cv::Scalar(7)));
    m.addLink(withData);
    EXPECT_TRUE(goOn(m).reduced.empty());
  }
}

TEST(ReduceGraph, TheReducedLocationNeverReachesTheLtmAndTheSavedGraphStaysConnected) {
  WithLtm ltm;
  MemoryOptions o = reducing();
  Memory m(o, &ltm.database);
  const int revisit = outAndBack(m);
  goOn(m);
  // R4 was saved with its link to R5 when it left STM: right after the reduction (a crash
  // here loses no more than the STM) the database has no link to R5 and has R1's to R4.
  m.joinLtmWriter();
  EXPECT_EQ(ltm.database.loadLinks(4).count(revisit), 0u);
  EXPECT_EQ(ltm.database.loadLinks(4).count(1), 1u);
  m.saveAll();
  const std::vector<int> ids = ltm.database.nodeIds();
  EXPECT_EQ(ids, (std::vector<int>{1, 3, 4, 6, 7}));
  for (const auto& [from, link] : ltm.database.loadAllLinks(true)) {
    EXPECT_NE(from, revisit);
    EXPECT_NE(link.to(), revisit) << from;
  }
  const std::multimap<int, Link> fromR1 = ltm.database.loadLinks(1);
  int merged = 0;
  for (const auto& [to, link] : fromR1) merged += link.type() == Link::kNeighborMerged ? 1 : 0;
  EXPECT_EQ(merged, 2);
  // From R1 every saved node is reachable through the saved links.
  EXPECT_EQ(ltm.database.neighborIds(1, 10).size(), ids.size());
  const db::ConsistencyReport report = ltm.database.checkConsistency(true);
  EXPECT_TRUE(report.ok()) << report.toString();
}

}  // namespace
}  // namespace rtabmap::memory

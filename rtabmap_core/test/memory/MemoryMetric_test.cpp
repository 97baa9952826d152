// What the SLAM pipeline asks of the memory beyond appearance-only loop closure: rehearsal of a
// moving robot, a location forgotten without trace, links added and removed, locations loaded
// by id, labels, and localization that never writes.
#include <gtest/gtest.h>

#include "MemoryTestPlaces.h"
#include "common/TestData.h"
#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/Memory.h"

namespace rtabmap::memory {
namespace {

using test::view;

LocationInput at(int place, int visit, double x) { return test::viewAt(place, visit, Transform(x, 0, 0, 0, 0, 0)); }

MemoryOptions metric() {
  MemoryOptions o;
  o.stmSize = 5;
  o.stillLinear = 0.1f;
  o.stillAngular = 0.1f;
  return o;
}

TEST(MemoryMetric, MovingRobotKeepsBothLocationsAndMovesTheWeight) {
  Memory m(metric());
  m.addLocation(at(1, 0, 0.0));
  AddResult moved = m.addLocation(at(1, 1, 0.5));  // same view, half a metre further
  EXPECT_FALSE(moved.merged);
  EXPECT_TRUE(moved.moving);
  ASSERT_NE(m.signature(1), nullptr);
  EXPECT_EQ(m.signature(2)->weight(), 1);
  EXPECT_EQ(m.signature(1)->weight(), 0);
  EXPECT_NEAR(m.signature(1)->link(2, Link::kNeighbor)->transform().x(), 0.5, 1e-9);
  // Still: the same place, merged as the paper says.
  AddResult still = m.addLocation(at(1, 2, 0.52));
  EXPECT_TRUE(still.merged);
  EXPECT_FALSE(still.moving);
  EXPECT_EQ(m.signature(2)->weight(), 2);

  MemoryOptions ignored = metric();
  ignored.rehearsalWeightIgnoredWhileMoving = true;
  Memory n(ignored);
  n.addLocation(at(1, 0, 0.0));
  n.addLocation(at(1, 1, 0.5));
  EXPECT_EQ(n.signature(2)->weight(), 0);
}

TEST(MemoryMetric, NeighbourLinkCarriesTheOdometryInformation) {
  Memory m(metric());
  m.addLocation(at(1, 0, 0.0));
  LocationInput next = at(2, 0, 1.0);
  next.odomInformation = Link::InfMatrix::Identity() * 400.0;
  m.addLocation(next);
  EXPECT_DOUBLE_EQ(m.signature(1)->link(2)->infMatrix()(0, 0), 400.0);
}

TEST(MemoryMetric, LastLocationIsForgottenWithoutTrace) {
  Memory m(metric());
  m.addLocation(at(1, 0, 0.0));
  const size_t words = m.vocabulary().size();
  m.addLocation(at(2, 0, 0.01));
  m.removeLastLocation();
  EXPECT_EQ(m.signature(2), nullptr);
  EXPECT_FALSE(m.signature(1)->hasLink(2));
  EXPECT_EQ(m.vocabulary().size(), words);
  EXPECT_EQ(m.stm(), (std::set<int>{1}));
  // The next location links to the one before the forgotten one.
  AddResult r = m.addLocation(at(3, 0, 1.0));
  EXPECT_TRUE(m.signature(1)->hasLink(r.id, Link::kNeighbor));
  EXPECT_NEAR(m.signature(1)->link(r.id)->transform().x(), 1.0, 1e-9);
}

TEST(MemoryMetric, LinksAddedAndRemovedOnBothEnds) {
  rtabmap::test::TempDir dir;
  db::Database ltm(dir.file("ltm.db"));
  MemoryOptions o = metric();
  o.stmSize = 1;
  Memory m(o, &ltm);
  for (int p = 1; p <= 4; ++p) m.addLocation(at(p, 0, p));
  const Link proximity(4, 1, Link::kLocalSpaceClosure, Transform(-3, 0, 0, 0, 0, 0));
  m.addLink(proximity);
  EXPECT_TRUE(m.signature(1)->hasLink(4, Link::kLocalSpaceClosure));
  EXPECT_NEAR(m.signature(1)->link(4, Link::kLocalSpaceClosure)->transform().x(), 3.0, 1e-9);
  EXPECT_EQ(m.signature(4)->weight(), 0) << "a proximity link moves no weight";
  EXPECT_TRUE(m.removeLink(4, 1, Link::kLocalSpaceClosure));
  EXPECT_FALSE(m.signature(1)->hasLink(4));
  EXPECT_FALSE(m.signature(4)->hasLink(1));
  EXPECT_FALSE(m.removeLink(100, 101, Link::kUndef));
}

// Five locations in a memory with a database (STM of one, no recent part of WM protected), the
// first of them transferred to the LTM.
struct FiveLocationsFirstInLtm {
  static MemoryOptions options() {
    MemoryOptions o = metric();
    o.stmSize = 1;
    o.recentWmRatio = 0.f;
    return o;
  }
  FiveLocationsFirstInLtm() {
    for (int p = 1; p <= 5; ++p) m.addLocation(at(p, 0, p));
    m.transfer({}, 0, 1, false);
  }
  rtabmap::test::TempDir dir;
  db::Database ltm{dir.file("ltm.db")};
  Memory m{options(), &ltm};
};

TEST(MemoryMetric, LocationsLoadedByIdAndLabels) {
  FiveLocationsFirstInLtm five;
  Memory& m = five.m;
  ASSERT_FALSE(m.inRam(1));
  EXPECT_TRUE(m.setLabel(1, "dock")) << "a label reaches a location in the LTM";
  EXPECT_TRUE(m.setLabel(5, "door"));
  EXPECT_FALSE(m.setLabel(77, "nowhere"));
  const std::vector<int> back = m.retrieveIds({1, 2, 5, 77});
  EXPECT_EQ(back, (std::vector<int>{1, 2}));
  ASSERT_TRUE(m.inRam(1));
  EXPECT_EQ(m.signature(1)->label(), "dock");
  EXPECT_EQ(m.signature(1)->getWords().size(), 100u);
  EXPECT_TRUE(m.wm().count(1));
}

// User data reaches a location not saved yet (the goals of RGBD/GoalsSavedInUserData): never
// over data it has, nor a saved or unknown location, nor in localization mode.
TEST(MemoryMetric, UserDataOnlyForANewLocationWithout) {
  FiveLocationsFirstInLtm five;
  Memory& m = five.m;
  ASSERT_FALSE(m.inRam(1));
  const std::string goal = "GOAL:7";
  const cv::Mat text = cv::Mat(1, static_cast<int>(goal.size()), CV_8UC1, const_cast<char*>(goal.data())).clone();
  std::string why;
  ASSERT_TRUE(m.setUserData(5, text, &why)) << why;
  EXPECT_EQ(cv::norm(codec::uncompressData(m.signature(5)->sensorData().userDataCompressed()), text, cv::NORM_INF), 0.0);
  EXPECT_FALSE(m.setUserData(5, cv::Mat(1, 3, CV_8UC1, cv::Scalar(1)), &why));
  EXPECT_NE(why.find("already has user data"), std::string::npos) << why;
  EXPECT_FALSE(m.setUserData(1, text, &why));
  EXPECT_NE(why.find("not in memory"), std::string::npos) << why;
  const std::vector<int> back = m.retrieveIds({2});
  ASSERT_EQ(back, std::vector<int>{2});
  EXPECT_FALSE(m.setUserData(2, text, &why));
  EXPECT_NE(why.find("already saved"), std::string::npos) << why;
  m.saveAll();
  const std::optional<Signature> saved = five.ltm.loadNode(5);
  ASSERT_TRUE(saved.has_value());
  EXPECT_EQ(cv::norm(codec::uncompressData(saved->sensorData().userDataCompressed()), text, cv::NORM_INF), 0.0);

  MemoryOptions localization = metric();
  localization.incremental = false;
  Memory l(localization, nullptr);
  AddResult r = l.addLocation(at(9, 0, 9.0));
  EXPECT_FALSE(l.setUserData(r.id, text, &why));
  EXPECT_NE(why.find("localization"), std::string::npos) << why;
}

TEST(MemoryMetric, LocalizationNeverWritesTheLtm) {
  rtabmap::test::TempDir dir;
  {
    db::Database ltm(dir.file("ltm.db"));
    MemoryOptions o = metric();
    o.stmSize = 1;
    Memory m(o, &ltm);
    for (int p = 1; p <= 4; ++p) m.addLocation(at(p, 0, p));
    m.saveAll();
  }
  db::DatabaseOptions readOnly;
  readOnly.readOnly = true;
  db::Database ltm(dir.file("ltm.db"), readOnly);
  MemoryOptions o = metric();
  o.incremental = false;
  o.stmSize = 0;  // a new location goes straight to WM, where it would be saved in mapping
  Memory m(o, &ltm);
  m.retrieveIds({1, 2, 3});
  AddResult r = m.addLocation(at(9, 0, 9.0));
  EXPECT_TRUE(m.wm().count(r.id));
  m.removeLastLocation();
  EXPECT_THROW(m.setLabel(4, "x"), std::logic_error) << "a label in the LTM would modify the map";
  EXPECT_NO_THROW(m.saveAll());  // nothing to write, and the read-only database is not touched
  m.transfer({}, 0, 1, false);
  EXPECT_EQ(m.wm().size(), 1u);
}

}  // namespace
}  // namespace rtabmap::memory

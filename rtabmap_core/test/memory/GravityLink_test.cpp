// Gravity links of new locations: where their orientation comes from (odometry or the IMU
// brought to the base), and that they follow a location through rehearsal and the LTM.
#include <gtest/gtest.h>

#include <cmath>

#include "MemoryTestPlaces.h"
#include "common/TestData.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/GravityLink.h"
#include "rtabmap_core/memory/Memory.h"

namespace rtabmap::memory {
namespace {

// Angle between two rotations (rad).
double angleBetween(const Transform& a, const Transform& b) {
  return a.quaternion().angularDistance(b.quaternion());
}

IMU imuOn(const Transform& baseInWorld, const Transform& imuOnBase) {
  IMU imu;
  imu.localTransform = imuOnBase;
  imu.orientation = (baseInWorld * imuOnBase).quaternion();
  imu.linearAcceleration = Eigen::Vector3d(0, 0, 9.81);
  return imu;
}

TEST(GravityLink, ImuOrientationIsBroughtToTheBase) {
  const Transform base(1, 2, 3, 0.1, -0.2, 0.7);
  // Mounted upside down and turned a quarter: the IMU's own orientation is far from the base's.
  const Transform mount(0.1, 0, 0.2, M_PI, 0, M_PI_2);
  const IMU imu = imuOn(base, mount);
  EXPECT_GT(angleBetween(Transform(0, 0, 0, imu.orientation.x(), imu.orientation.y(), imu.orientation.z(),
                                   imu.orientation.w()),
                         base),
            1.0);
  const Transform r = baseOrientationFromImu(imu);
  ASSERT_FALSE(r.isNull());
  EXPECT_LT(angleBetween(r, base), 1e-9);
  EXPECT_NEAR(r.translation().norm(), 0.0, 1e-12) << "an orientation only";
  IMU noOrientation = imu;
  noOrientation.orientation = Eigen::Quaterniond(0, 0, 0, 0);
  EXPECT_TRUE(baseOrientationFromImu(noOrientation).isNull());
}

TEST(GravityLink, SourceIsTheOdometryOrTheImu) {
  const Transform odom(4, 5, 0.3, 0.05, 0.1, 1.2);
  const Transform truth(4, 5, 0.3, -0.02, 0.03, 0.4);  // what the IMU says
  const IMU imu = imuOn(truth, Transform(0, 0, 0.1, 0, 0, 0));

  const std::optional<Link> fromOdom = gravityLinkOf(7, odom, imu, true);
  ASSERT_TRUE(fromOdom);
  EXPECT_EQ(fromOdom->from(), 7);
  EXPECT_EQ(fromOdom->to(), 7);
  EXPECT_EQ(fromOdom->type(), Link::kGravity);
  EXPECT_LT(angleBetween(fromOdom->transform(), odom), 1e-9);
  EXPECT_NEAR(fromOdom->transform().translation().norm(), 0.0, 1e-12);

  const std::optional<Link> fromImu = gravityLinkOf(7, odom, imu, false);
  ASSERT_TRUE(fromImu);
  EXPECT_LT(angleBetween(fromImu->transform(), truth), 1e-9);

  EXPECT_FALSE(gravityLinkOf(7, odom, IMU(), false)) << "no IMU orientation, odometry not trusted for gravity";
  EXPECT_TRUE(gravityLinkOf(7, odom, IMU(), true));
  EXPECT_FALSE(gravityLinkOf(7, Transform(), imu, false)) << "a location without a pose has no gravity link";
  EXPECT_FALSE(gravityLinkOf(7, Transform(), imu, true));
}

MemoryOptions gravityFromOdometry() {
  MemoryOptions o;
  o.stmSize = 1;
  o.recentWmRatio = 0.f;
  o.stillLinear = 0.1f;
  o.stillAngular = 0.1f;
  o.useOdomGravity = true;
  return o;
}

TEST(GravityLink, EveryLocationWithAPoseGetsItsOwn) {
  Memory m(gravityFromOdometry());
  for (int p = 1; p <= 3; ++p) m.addLocation(test::viewAt(p, 0, Transform(p, 0, 0, 0, 0.1 * p, 0)));
  for (int id = 1; id <= 3; ++id) {
    const Signature* s = m.signature(id);
    ASSERT_NE(s, nullptr);
    const Link* g = s->link(id, Link::kGravity);
    ASSERT_NE(g, nullptr) << "location " << id;
    EXPECT_NEAR(g->transform().pitch(), 0.1 * id, 1e-9);
    EXPECT_EQ(s->getNeighborLinks().count(id), 0u) << "a gravity link joins no two locations";
  }
  MemoryOptions off = gravityFromOdometry();
  off.useOdomGravity = false;
  Memory n(off);
  n.addLocation(test::viewAt(1, 0, Transform(1, 0, 0, 0, 0.1, 0)));
  EXPECT_FALSE(n.signature(1)->hasLink(1, Link::kGravity)) << "no IMU orientation in the frame";
  LocationInput withImu = test::viewAt(2, 0, Transform(2, 0, 0, 0, 0.1, 0));
  withImu.data.setIMU(imuOn(Transform(0, 0, 0, 0, 0.05, 0), Transform::Identity()));
  n.addLocation(withImu);
  ASSERT_TRUE(n.signature(2)->hasLink(2, Link::kGravity));
  EXPECT_NEAR(n.signature(2)->link(2, Link::kGravity)->transform().pitch(), 0.05, 1e-9);
}

TEST(GravityLink, RehearsalKeepsOnlyTheKeptLocationsOwn) {
  MemoryOptions o = gravityFromOdometry();
  o.stmSize = 5;
  for (bool newId : {false, true}) {
    o.rehearsalIdUpdatedToNewOne = newId;
    Memory m(o);
    m.addLocation(test::viewAt(1, 0, Transform(0, 0, 0, 0, 0.1, 0)));
    const AddResult r = m.addLocation(test::viewAt(1, 1, Transform(0.01, 0, 0, 0, 0.1, 0)));  // still: merged
    ASSERT_TRUE(r.merged);
    const Signature* kept = m.signature(r.id);
    ASSERT_NE(kept, nullptr);
    EXPECT_FALSE(kept->hasLink(r.mergedWith)) << "the removed location's gravity link moved as a link to it";
    int gravity = 0;
    for (const auto& [to, link] : kept->getLinks()) gravity += link.type() == Link::kGravity && to == r.id;
    EXPECT_EQ(gravity, 1);
  }
}

TEST(GravityLink, SavedAndRetrievedWithTheLocation) {
  rtabmap::test::TempDir dir;
  db::Database ltm(dir.file("ltm.db"));
  Memory m(gravityFromOdometry(), &ltm);
  for (int p = 1; p <= 4; ++p) m.addLocation(test::viewAt(p, 0, Transform(p, 0, 0, 0.02 * p, -0.03, 0)));
  m.transfer({}, 0, 1, false);
  ASSERT_FALSE(m.inRam(1));
  EXPECT_EQ(m.retrieveIds({1}), (std::vector<int>{1}));
  const Link* g = m.signature(1)->link(1, Link::kGravity);
  ASSERT_NE(g, nullptr);
  EXPECT_NEAR(g->transform().roll(), 0.02, 1e-6);
  EXPECT_NEAR(g->transform().pitch(), -0.03, 1e-6);
}

}  // namespace
}  // namespace rtabmap::memory

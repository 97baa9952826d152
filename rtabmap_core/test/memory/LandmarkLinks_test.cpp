// Landmark links of new locations: one per landmark seen, weighted by its covariance, kept
// through rehearsal and the LTM, and never a neighbour in the graph of places.
#include <gtest/gtest.h>

#include <cmath>

#include "MemoryTestPlaces.h"
#include "common/TestData.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/LandmarkLinks.h"
#include "rtabmap_core/memory/Memory.h"

namespace rtabmap::memory {
namespace {

Landmark landmark(int id, const Transform& pose, double linear = 0.001, double angular = 0.01) {
  Landmark l;
  l.id = id;
  l.size = 0.2f;
  l.pose = pose;
  l.covariance.setZero();
  l.covariance.diagonal() << linear, linear, linear, angular, angular, angular;
  return l;
}

TEST(LandmarkLinks, OneLinkPerLandmarkWithTheInverseCovariance) {
  Landmarks seen;
  seen[3] = landmark(3, Transform(1.0, 0.2, 0.4, 0, 0, 0.5));
  Landmark full = landmark(8, Transform(2.0, -0.5, 0.1, 0.1, 0, 0));
  full.covariance(0, 1) = full.covariance(1, 0) = 0.0005;  // correlated x and y
  seen[8] = full;
  std::vector<std::string> why;
  const std::vector<Link> links = landmarkLinksOf(5, seen, &why);
  EXPECT_TRUE(why.empty());
  ASSERT_EQ(links.size(), 2u);
  EXPECT_EQ(links[0].from(), 5);
  EXPECT_EQ(links[0].to(), -3);
  EXPECT_EQ(links[0].type(), Link::kLandmark);
  EXPECT_NEAR((links[0].transform().inverse() * seen[3].pose).getNorm(), 0.0, 1e-12);
  EXPECT_NEAR(links[0].infMatrix()(0, 0), 1000.0, 1e-6);
  EXPECT_NEAR(links[0].infMatrix()(5, 5), 100.0, 1e-6);
  EXPECT_EQ(links[1].to(), -8);
  const Eigen::Matrix<double, 6, 6> product = links[1].infMatrix() * full.covariance;
  EXPECT_TRUE(product.isApprox(Eigen::Matrix<double, 6, 6>::Identity(), 1e-9)) << product;
}

TEST(LandmarkLinks, UnusableLandmarksAreLeftOutWithTheReason) {
  Landmarks seen;
  seen[0] = landmark(0, Transform(1, 0, 0, 0, 0, 0));
  seen[1] = landmark(1, Transform());
  seen[2] = landmark(2, Transform(1, 0, 0, 0, 0, 0), 0.0);
  seen[4] = landmark(4, Transform(1, 0, 0, 0, 0, 0), std::nan(""));
  seen[6] = landmark(6, Transform(1, 0, 0, 0, 0, 0));
  std::vector<std::string> why;
  const std::vector<Link> links = landmarkLinksOf(9, seen, &why);
  ASSERT_EQ(links.size(), 1u);
  EXPECT_EQ(links[0].to(), -6);
  ASSERT_EQ(why.size(), 4u);
  EXPECT_NE(why[0].find("landmark 0"), std::string::npos);
  EXPECT_NE(why[1].find("no valid pose"), std::string::npos);
  EXPECT_NE(why[2].find("covariance"), std::string::npos);
  EXPECT_NE(why[3].find("covariance"), std::string::npos);
}

MemoryOptions metric() {
  MemoryOptions o;
  o.stmSize = 1;
  o.recentWmRatio = 0.f;
  o.stillLinear = 0.1f;
  o.stillAngular = 0.1f;
  return o;
}

LocationInput seeing(int place, int visit, const Transform& pose, const Landmarks& landmarks) {
  LocationInput in = test::viewAt(place, visit, pose);
  in.data.setLandmarks(landmarks);
  return in;
}

TEST(LandmarkLinks, LocationsLinkToWhatTheySeeNotToEachOtherThroughIt) {
  Memory m(metric());
  m.addLocation(seeing(1, 0, Transform(0, 0, 0, 0, 0, 0), {{3, landmark(3, Transform(2, 0, 0, 0, 0, 0))}}));
  m.addLocation(seeing(2, 0, Transform(1, 0, 0, 0, 0, 0), {{3, landmark(3, Transform(1, 0, 0, 0, 0, 0))}}));
  for (int id : {1, 2}) {
    const Signature* s = m.signature(id);
    ASSERT_NE(s, nullptr);
    ASSERT_NE(s->link(-3, Link::kLandmark), nullptr) << id;
    EXPECT_EQ(s->getNeighborLinks().count(-3), 0u) << "a landmark is not a place";
  }
  EXPECT_EQ(m.neighbors(1, 3).count(-3), 0u) << "nor a neighbour of the Bayes filter's transition";
}

TEST(LandmarkLinks, RehearsalKeepsWhatEitherLocationSaw) {
  MemoryOptions o = metric();
  o.stmSize = 5;
  for (bool newId : {false, true}) {
    o.rehearsalIdUpdatedToNewOne = newId;
    Memory m(o);
    // The same place, the robot still (1 cm); each view saw a different marker.
    m.addLocation(seeing(1, 0, Transform(0, 0, 0, 0, 0, 0), {{3, landmark(3, Transform(2, 0, 0, 0, 0, 0))}}));
    const AddResult r =
        m.addLocation(seeing(1, 1, Transform(0.01, 0, 0, 0, 0, 0), {{4, landmark(4, Transform(0, 1.5, 0, 0, 0, 0))}}));
    ASSERT_TRUE(r.merged);
    const Signature* kept = m.signature(r.id);
    ASSERT_NE(kept, nullptr);
    const Link* three = kept->link(-3, Link::kLandmark);
    const Link* four = kept->link(-4, Link::kLandmark);
    ASSERT_NE(three, nullptr) << "newId " << newId;
    ASSERT_NE(four, nullptr) << "newId " << newId;
    // Each from the kept location's pose: the removed one was 1 cm ahead of the first view.
    const Transform keptPose = newId ? Transform(0.01, 0, 0, 0, 0, 0) : Transform::Identity();
    EXPECT_NEAR((keptPose * three->transform()).x(), 2.0, 1e-9);
    EXPECT_NEAR((keptPose * four->transform()).x(), 0.01, 1e-9);
    EXPECT_NEAR((keptPose * four->transform()).y(), 1.5, 1e-9);
  }
}

TEST(LandmarkLinks, SavedAndRetrievedWithTheLocation) {
  rtabmap::test::TempDir dir;
  db::Database ltm(dir.file("ltm.db"));
  Memory m(metric(), &ltm);
  m.addLocation(seeing(1, 0, Transform(1, 0, 0, 0, 0, 0), {{7, landmark(7, Transform(0.5, 1.0, 0.3, 0, 0, 1.0))}}));
  for (int p = 2; p <= 4; ++p) m.addLocation(test::viewAt(p, 0, Transform(p, 0, 0, 0, 0, 0)));
  m.transfer({}, 0, 1, false);
  ASSERT_FALSE(m.inRam(1));
  EXPECT_EQ(m.retrieveIds({1}), (std::vector<int>{1}));
  const Link* l = m.signature(1)->link(-7, Link::kLandmark);
  ASSERT_NE(l, nullptr);
  EXPECT_NEAR(l->transform().y(), 1.0, 1e-6);
  EXPECT_NEAR(l->transform().yaw(), 1.0, 1e-6);
  EXPECT_NEAR(l->infMatrix()(0, 0), 1000.0, 1e-3);
}

}  // namespace
}  // namespace rtabmap::memory

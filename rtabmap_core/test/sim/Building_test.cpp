// Generated buildings: closed, connected, navigable, deterministic, and with plain walls among
// the textured ones.
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <cmath>

#include "SimTestUtil.h"
#include "rtabmap_core/sim/Materials.h"

using namespace rtabmap::sim;

TEST(SimBuilding, EveryRoomHasADoorAndEveryNodeIsReachable) {
  const Building& b = test::loopBuilding();
  EXPECT_GE(b.roomCount(), 12);
  for (const Area& a : b.areas) {
    if (a.kind == AreaKind::kRoom) {
      EXPECT_FALSE(a.doors.empty()) << a.name;
    }
  }
  const int start = b.nav.junction(0, 0);
  ASSERT_GE(start, 0);
  for (size_t k = 0; k < b.nav.nodes().size(); ++k) EXPECT_FALSE(b.nav.shortestPath(start, static_cast<int>(k)).empty()) << k;
}

TEST(SimBuilding, IsClosedAndItsNavigationEdgesAreClearOfSolids) {
  const Building& b = test::loopBuilding();
  const World& w = *b.world;
  std::vector<RayHit> hits;
  for (const NavNode& n : b.nav.nodes()) {
    EXPECT_FALSE(w.insideSolid(n.position));
    for (int k = 0; k < 36; ++k) {
      const double a = k * M_PI / 18.0;
      EXPECT_TRUE(w.castRay(n.position, {std::cos(a), std::sin(a)}, 200.0, static_cast<float>(w.ceilingHeight()) - 1e-3f, hits));
    }
    // Straight lines along every edge (through doorways too) keep 0.45 m from any solid.
    for (const NavEdge& e : b.nav.edges(static_cast<int>(&n - &b.nav.nodes()[0]))) {
      std::vector<Eigen::Vector2d> pts = {n.position};
      pts.insert(pts.end(), e.via.begin(), e.via.end());
      pts.push_back(b.nav.nodes()[static_cast<size_t>(e.to)].position);
      for (size_t i = 0; i + 1 < pts.size(); ++i) {
        const double len = (pts[i + 1] - pts[i]).norm();
        for (double s = 0.0; s <= len; s += 0.1) {
          const Eigen::Vector2d p = pts[i] + (pts[i + 1] - pts[i]) * (len > 0 ? s / len : 0.0);
          ASSERT_GT(w.clearance(p, 0.05f), 0.45) << "at " << p.transpose();
        }
      }
    }
  }
}

TEST(SimBuilding, SameSeedSameBuildingOtherSeedAnother) {
  const BuildingSpec spec = test::fastSpec(scenarioSpec("loop").building);
  const Building a = generateBuilding(spec, 21);
  const Building b = generateBuilding(spec, 21);
  const Building c = generateBuilding(spec, 22);
  ASSERT_EQ(a.world->faces().size(), b.world->faces().size());
  for (size_t i = 0; i < a.world->faces().size(); ++i) {
    ASSERT_EQ(a.world->faces()[i].a, b.world->faces()[i].a);
    ASSERT_EQ(a.world->faces()[i].material.texture, b.world->faces()[i].material.texture);
  }
  ASSERT_EQ(a.world->textures().size(), b.world->textures().size());
  for (size_t i = 0; i < a.world->textures().size(); ++i) {
    ASSERT_EQ(cv::norm(a.world->textures()[i].image(), b.world->textures()[i].image(), cv::NORM_INF), 0.0);
  }
  EXPECT_NE(a.width, c.width);
  EXPECT_THROW(generateBuilding(BuildingSpec{0}, 1), std::invalid_argument);
}

TEST(SimBuilding, SomeWallsArePlainAndMostRoomsHavePictures) {
  const Building& b = test::loopBuilding();
  const World& w = *b.world;
  int plain = 0, textured = 0;
  for (const Face& f : w.faces()) {
    if (f.length < 1.0 || w.solids()[static_cast<size_t>(f.solid)].kind != SolidKind::kWall) continue;
    // Paint textures are (nearly) uniform: their coarse levels show no contrast.
    const cv::Mat img = w.textures()[static_cast<size_t>(f.material.texture)].image(2);
    cv::Scalar mean, sd;
    cv::meanStdDev(img, mean, sd);
    (sd[0] < 2.0 ? plain : textured)++;
  }
  EXPECT_GT(plain, 20);
  EXPECT_GT(textured, 20);
  EXPECT_GT(w.decals().size(), 30u);
}

TEST(SimBuilding, TheCorridorScenarioHasALongPlainCorridor) {
  const Building b = generateBuilding(test::fastSpec(scenarioSpec("corridor").building), 3);
  EXPECT_GT(b.width, 40.0);
  const World& w = *b.world;
  double plainLength = 0.0, totalLength = 0.0;
  for (const Face& f : w.faces()) {
    if (w.solids()[static_cast<size_t>(f.solid)].kind != SolidKind::kWall || f.length < 0.5) continue;
    const Eigen::Vector2d in = 0.5 * (f.a + f.b) + 0.3 * f.normal;
    bool corridor = false;
    for (const Area& a : b.areas) corridor = corridor || (a.kind == AreaKind::kCorridor && a.rect.contains(in));
    if (!corridor) continue;
    cv::Scalar mean, sd;
    cv::meanStdDev(w.textures()[static_cast<size_t>(f.material.texture)].image(2), mean, sd);
    totalLength += f.length;
    if (sd[0] < 2.0 && f.decalCount <= 1) plainLength += f.length;
  }
  EXPECT_GT(totalLength, 100.0);
  EXPECT_GT(plainLength, 0.8 * totalLength);
}

// RGBD/ProximityGlobalScanMap: in localization mode the new scan is matched against one map
// assembled from the scans of every node of the saved map (Long-Term Memory included), around
// where the robot is assumed.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>

#include "../../src/slam/GlobalScanMap.h"
#include "common/TestData.h"
#include "registration/IcpTestScenes.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap {
namespace {

// The robot's lidar in the office: 12 m range, `noise` (m) on the ranges.
test::Lidar2D officeLidar(double noise) {
  test::Lidar2D lidar;
  lidar.rangeMax = 12.0;
  lidar.noise = noise;
  return lidar;
}

// Scans of the office at these poses, each with the pose of its node.
std::vector<std::pair<LaserScan, Transform>> officeScans(const std::vector<Transform>& poses) {
  const test::Lidar2D lidar = officeLidar(0.0);
  std::vector<std::pair<LaserScan, Transform>> parts;
  for (const Transform& p : poses) parts.emplace_back(test::castScan2D(test::officeWorld(), p, lidar), p);
  return parts;
}

GlobalScanMap officeMap(float voxelSize) {
  GlobalScanMap map(voxelSize);
  map.add(officeScans({Transform(2, 2, 0), Transform(2, 6, 1.5)}));
  map.add(officeScans({Transform(9, 6, 0), Transform(10, 10, -1.5)}));
  map.finish();
  return map;
}

TEST(GlobalScanMap, AroundGivesThePointsNearThePoseInItsFrame) {
  const GlobalScanMap map = officeMap(0.05f);
  ASSERT_FALSE(map.empty());
  // Everything, in the map frame.
  const LaserScan all = map.around(Transform::Identity(), 1000.0f);
  ASSERT_EQ(all.size(), map.points());
  const Transform center(8.0, 5.0, 0.0, 0.0, 0.0, 0.7);
  const float radius = 3.0f;
  int expected = 0;
  for (int i = 0; i < all.size(); ++i) {
    const Eigen::Vector3f p = all.point(i);
    if (std::hypot(p.x() - center.x(), p.y() - center.y()) <= radius) ++expected;
  }
  const LaserScan near = map.around(center, radius);
  ASSERT_GT(expected, 20);
  EXPECT_EQ(near.size(), expected) << "the cell index must find every point within the radius, and only those";
  for (int i = 0; i < near.size(); ++i) {
    const Eigen::Vector3f p = near.point(i);
    EXPECT_LE(p.head<2>().norm(), radius + 1e-4f) << "not in the pose's frame";
    // Back in the map frame, the point is on a wall of the office.
    const Transform m = center * Transform(p.x(), p.y(), 0.0, 0.0, 0.0, 0.0);
    double nearestWall = 1e9;
    for (const test::Segment& s : test::officeWorld()) {
      const Eigen::Vector2d a(s.x1, s.y1), b(s.x2, s.y2), q(m.x(), m.y());
      const double u = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      nearestWall = std::min(nearestWall, (a + u * (b - a) - q).norm());
    }
    EXPECT_LT(nearestWall, 0.05) << "point " << i;
  }
  EXPECT_TRUE(map.around(Transform(100.0, 100.0, 0.0), 3.0f).empty());
}

TEST(GlobalScanMap, OverlappingScansShareTheirVoxels) {
  GlobalScanMap once(0.05f);
  once.add(officeScans({Transform(2, 2, 0)}));
  once.finish();
  GlobalScanMap twice(0.05f);
  twice.add(officeScans({Transform(2, 2, 0)}));
  twice.add(officeScans({Transform(2, 2, 0)}));  // another batch: joined by finish()'s filter
  twice.finish();
  GlobalScanMap raw(0.0f);
  raw.add(officeScans({Transform(2, 2, 0)}));
  raw.add(officeScans({Transform(2, 2, 0)}));
  raw.finish();
  ASSERT_GT(once.points(), 100);
  EXPECT_NEAR(twice.points(), once.points(), once.points() / 50);
  EXPECT_GT(raw.points(), 3 * once.points() / 2) << "voxel size 0 keeps every point";
}

TEST(GlobalScanMap, ScansOfAnotherFormatAreSkipped) {
  GlobalScanMap map(0.05f);
  map.add(officeScans({Transform(2, 2, 0)}));
  const int before = [&] {
    GlobalScanMap copy(0.05f);
    copy.add(officeScans({Transform(2, 2, 0)}));
    copy.finish();
    return copy.points();
  }();
  map.add({{test::castScan3D(test::hallWorld(), Transform::Identity(), 4, 90), Transform::Identity()}});
  map.finish();
  EXPECT_EQ(map.skippedParts(), 1);
  EXPECT_EQ(map.points(), before);
  EXPECT_TRUE(map.around(Transform::Identity(), 5.0f).is2d());
}

// --- localization on a saved map ---

ParametersMap lidarRobot(bool mapping, bool globalScanMap) {
  return {{Parameters::kRtabmapDetectionRate(), "0"},
          {Parameters::kRegStrategy(), "1"},
          {Parameters::kRegForce3DoF(), "true"},
          {Parameters::kKpMaxFeatures(), "-1"},
          {Parameters::kRGBDNeighborLinkRefining(), "true"},
          {Parameters::kRGBDProximityPathMaxNeighbors(), "3"},
          {Parameters::kRGBDCreateOccupancyGrid(), "false"},
          {Parameters::kIcpPointToPlane(), "true"},
          {Parameters::kIcpVoxelSize(), "0.05"},
          {Parameters::kIcpMaxCorrespondenceDistance(), "0.3"},
          {Parameters::kIcpIterations(), "30"},
          {Parameters::kIcpMaxTranslation(), "1"},
          // A small Working Memory: most of the map is in the database when localization starts.
          {Parameters::kMemSTMSize(), "2"},
          {Parameters::kRtabmapMemoryThr(), "5"},
          {Parameters::kMemIncrementalMemory(), mapping ? "true" : "false"},
          {Parameters::kRGBDProximityGlobalScanMap(), globalScanMap ? "true" : "false"}};
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

struct Localized {
  std::vector<double> errors;  // per update, m
  std::vector<bool> localized;
  SlamSummary summary;
};

// Localization along `route` (true poses) from `given` (null: none), odometry from identity
// drifting like wheels.
Localized localize(const std::string& db, const std::vector<Transform>& route, const Transform& given,
                   bool globalScanMap) {
  Rtabmap slam;
  slam.init(lidarRobot(false, globalScanMap), db);
  if (!given.isNull()) {
    EXPECT_TRUE(slam.setInitialPose(given));
  }
  const test::Lidar2D lidar = officeLidar(0.01);
  std::mt19937 rng(test::drawSeed(11));
  const std::vector<Transform> odom = test::wheelOdometry(route, 0.02, 0.02);
  Localized out;
  for (size_t i = 0; i < route.size(); ++i) {
    const Transform o = odom.front().inverse() * odom[i];
    const bool used = slam.process(SensorData(test::castScan2D(test::officeWorld(), route[i], lidar, &rng),
                                              static_cast<int>(i) + 1, 100.0 + i),
                                   o, Eigen::Matrix<double, 6, 6>::Identity() * 1e-4);
    out.localized.push_back(used);
    out.errors.push_back(slam.currentPose().getDistance(route[i]));
  }
  out.summary = slam.summary();
  slam.close();
  return out;
}

class GlobalScanMapLocalization : public ::testing::Test {
 protected:
  void SetUp() override {
    // The map: a tour of the office with drifting wheel odometry, corrected by the scans.
    const std::vector<Transform> tour =
        test::pathThrough({{2, 2}, {2, 6}, {10, 6}, {10, 10}, {12.5, 10}}, 0.25);
    const test::Lidar2D lidar = officeLidar(0.01);
    std::mt19937 rng(test::drawSeed(5));
    const std::vector<Transform> odom = test::wheelOdometry(tour, 0.02, 0.02);
    Rtabmap slam;
    slam.init(lidarRobot(true, false), db_);
    for (size_t i = 0; i < tour.size(); ++i) {
      slam.process(SensorData(test::castScan2D(test::officeWorld(), tour[i], lidar, &rng), static_cast<int>(i) + 1,
                              static_cast<double>(i)),
                   odom[i], Eigen::Matrix<double, 6, 6>::Identity() * 1e-4);
    }
    transferred_ = slam.summary().transferred;
    slam.close();
  }

  test::TempDir dir_{"rtabmap_global_scan_map"};
  const std::string db_ = dir_.file("map.db");
  int transferred_ = 0;
};

TEST_F(GlobalScanMapLocalization, RobotPlacedByTheUserLocalisesOnTheWholeMap) {
  ASSERT_GT(transferred_, 20) << "the map should be mostly in the database";
  const std::string before = fileBytes(db_);
  // Back through the office the other way, from the door between the two rooms, then 2 m
  // beside the mapped trajectory (which went along x = 2): walls it saw, from where it never was.
  const std::vector<Transform> toCorner = test::pathThrough({{8, 6}, {4, 6}}, 0.25);
  const std::vector<Transform> route = test::pathThrough({{8, 6}, {4, 6}, {4, 2}}, 0.25);
  const size_t aside = toCorner.size() + 16;  // past the turn, well away from the map's nodes
  ASSERT_GT(route.size(), aside + 5);
  const Transform given = route.front() * Transform(0.25, -0.2, 0.0, 0.0, 0.0, 0.06);

  const Localized global = localize(db_, route, given, true);
  int first = -1, localizedAside = 0;
  for (size_t k = 0; k < global.localized.size(); ++k) {
    if (global.localized[k] && first < 0) first = static_cast<int>(k);
    // Against the world: the map itself keeps a few centimetres of the mapping's drift there
    // (worst error 3.3-4.7 cm over 17 draws of the noise).
    if (first >= 0) {
      EXPECT_LT(global.errors[k], 0.06) << "update " << k;
    }
    if (k >= aside && global.localized[k]) ++localizedAside;
  }
  // The first match waits for a second one to agree with it (RGBD/MaxOdomCacheSize).
  EXPECT_GE(first, 0) << "never localised";
  EXPECT_LE(first, 2);
  EXPECT_GE(localizedAside, static_cast<int>(route.size() - aside) / 3)
      << "the whole map is matched, not only the trajectory's nodes nearby";
  EXPECT_EQ(fileBytes(db_), before) << "localization must not modify the database";

  // Local paths (the default) localise only near the mapped trajectory
  // (RGBD/ProximityPathFilteringRadius): beside it the robot goes on by odometry alone.
  const Localized paths = localize(db_, route, given, false);
  int pathsAside = 0;
  for (size_t k = aside; k < paths.localized.size(); ++k) pathsAside += paths.localized[k] ? 1 : 0;
  EXPECT_LT(pathsAside, localizedAside);
  std::cout << "localised beside the mapped trajectory: " << localizedAside << " of " << route.size() - aside
            << " updates on the global scan map, " << pathsAside << " on local paths; worst error "
            << *std::max_element(global.errors.begin() + first + 1, global.errors.end()) << " m vs "
            << *std::max_element(paths.errors.begin() + first + 1, paths.errors.end()) << " m" << std::endl;
  EXPECT_EQ(fileBytes(db_), before);
}

TEST_F(GlobalScanMapLocalization, RobotAssumedOffTheMapNeverLocalises) {
  const std::vector<Transform> route = test::pathThrough({{8, 6}, {3, 6}}, 0.25);
  // Told it is 30 m away from everything: no node of the map is within RGBD/LocalRadius.
  const Localized run = localize(db_, route, Transform(40.0, 40.0, 0.0), true);
  EXPECT_EQ(run.summary.localizations, 0);
  for (double e : run.errors) EXPECT_GT(e, 30.0);
}

}  // namespace
}  // namespace rtabmap

// Local grids from 2D laser scans: 2D ray tracing, range limits, unknown space, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "maps/MapsTestUtil.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/LocalGridMaker.h"
#include "rtabmap_core/maps/LocalGridStages.h"

using namespace rtabmap;
using rtabmap::test::countIn;

namespace {

LocalGridOptions scanOptions() {
  LocalGridOptions o;
  o.sensor = LocalGridOptions::Sensor::kScan;
  o.cellSize = 0.1f;
  o.rangeMax = 0.0f;
  return o;
}

bool hasCell(const cv::Mat& cells, float x, float y, float c) {
  return countIn(cells, x - c / 2 + 1e-4, y - c / 2 + 1e-4, x + c / 2 - 1e-4, y + c / 2 - 1e-4) > 0;
}

}  // namespace

TEST(LocalGridScan, OneBeamMarksFreeCellsUpToTheHitAndTheHitOccupied) {
  // One beam straight ahead hitting at 2.02 m: free cells 0.0..1.9, obstacle in cell [2.0, 2.1).
  const LaserScan scan = LaserScan::fromRanges({2.02f}, 0.0, 0.01, 0.0, 10.0);
  const LocalGrid g = rayTraceScan2D(scan, scanOptions());
  ASSERT_EQ(g.obstacles.total(), 1u);
  EXPECT_NEAR(g.obstacles.ptr<float>()[0], 2.02f, 1e-5);  // the hit itself, not the cell centre
  EXPECT_EQ(g.empty.total(), 20u);  // cells 0..19 along x
  for (int i = 0; i < 20; ++i) EXPECT_TRUE(hasCell(g.empty, 0.05f + 0.1f * i, 0.05f, 0.1f)) << i;
  EXPECT_FALSE(hasCell(g.empty, 2.05f, 0.05f, 0.1f));
  EXPECT_TRUE(g.ground.empty());
  EXPECT_EQ(g.obstacles.type(), CV_32FC2);
}

TEST(LocalGridScan, RoomScanHasWallsOccupiedInsideFreeAndNothingBehindWalls) {
  const auto world = test::World2D::room(-2, -1.5, 3, 1.5);
  const LaserScan scan = test::simulateScan(world, Transform::Identity(), 361, 2 * M_PI * 359 / 360, 10);
  LocalGridOptions o = scanOptions();
  o.cellSize = 0.05f;
  const LocalGridResult r = createLocalGrid(SensorData(scan), o);
  ASSERT_TRUE(r.success) << r.why;
  EXPECT_EQ(r.source, "scan 2D");
  const LocalGrid& g = r.grid;
  // Every obstacle lies on a wall (within half a cell).
  const float* p = g.obstacles.ptr<float>();
  for (size_t i = 0; i < g.obstacles.total(); ++i, p += 2) {
    const bool onWall = std::abs(p[0] + 2) < 0.03 || std::abs(p[0] - 3) < 0.03 ||
                        std::abs(p[1] + 1.5) < 0.03 || std::abs(p[1] - 1.5) < 0.03;
    EXPECT_TRUE(onWall) << p[0] << " " << p[1];
  }
  EXPECT_GT(g.obstacles.total(), 200u);
  // Free space fills the room near the robot, never beyond the walls.
  EXPECT_TRUE(hasCell(g.empty, 1.025f, 0.025f, 0.05f));
  EXPECT_TRUE(hasCell(g.empty, -1.025f, -0.525f, 0.05f));
  EXPECT_EQ(countIn(g.empty, 3.05, -5, 10, 5), 0);
  EXPECT_EQ(countIn(g.empty, -10, 1.55, 10, 10), 0);
  // No cell is both free and occupied.
  const Cloud obs = cloudFromCells(g.obstacles);
  for (const auto& q : obs.points) EXPECT_FALSE(hasCell(g.empty, (std::floor(q.x / 0.05f) + 0.5f) * 0.05f, (std::floor(q.y / 0.05f) + 0.5f) * 0.05f, 0.05f));
}

TEST(LocalGridScan, LocalTransformPutsTheGridInTheBaseFrame) {
  LaserScan scan = LaserScan::fromRanges({1.0f}, 0.0, 0.01, 0.0, 10.0, Transform(0.5, 0.2, 0.3, 0, 0, M_PI / 2));
  const LocalGrid g = rayTraceScan2D(scan, scanOptions());
  ASSERT_EQ(g.obstacles.total(), 1u);
  EXPECT_NEAR(g.obstacles.ptr<float>()[0], 0.5f, 1e-5);
  EXPECT_NEAR(g.obstacles.ptr<float>()[1], 1.2f, 1e-5);
  EXPECT_NEAR(g.viewPoint.z(), 0.3f, 1e-6);
  EXPECT_TRUE(hasCell(g.empty, 0.55f, 0.65f, 0.1f));
}

TEST(LocalGridScan, BeamsBeyondRangeMaxAreFreeOnlyUpToRangeMax) {
  const LaserScan scan = LaserScan::fromRanges({6.0f}, 0.0, 0.01, 0.0, 10.0);
  LocalGridOptions o = scanOptions();
  o.rangeMax = 3.0f;
  ScanRayTracingStats s;
  const LocalGrid g = rayTraceScan2D(scan, o, &s);
  EXPECT_EQ(s.beyondRangeMax, 1);
  EXPECT_TRUE(g.obstacles.empty());
  EXPECT_TRUE(hasCell(g.empty, 2.95f, 0.05f, 0.1f));
  EXPECT_FALSE(hasCell(g.empty, 3.15f, 0.05f, 0.1f));  // the cell at 3.0 m is the last
}

TEST(LocalGridScan, RangeMinDropsCloseReturns) {
  const LaserScan scan = LaserScan::fromRanges({0.1f, 2.0f}, 0.0, 0.5, 0.0, 10.0);
  LocalGridOptions o = scanOptions();
  o.rangeMin = 0.2f;
  ScanRayTracingStats s;
  const LocalGrid g = rayTraceScan2D(scan, o, &s);
  EXPECT_EQ(s.belowRangeMin, 1);
  EXPECT_EQ(g.obstacles.total(), 1u);
}

TEST(LocalGridScan, UnknownSpaceFilledTracesTheMissingBeamsFreeWithoutObstacle) {
  // 181 beams over 180 degrees, the left half without return (+inf: dropped by fromRanges).
  std::vector<float> ranges(181, 2.0f);
  for (int i = 91; i < 181; ++i) ranges[i] = std::numeric_limits<float>::infinity();
  const LaserScan scan = LaserScan::fromRanges(ranges, -M_PI / 2, M_PI / 180, 0.0, 4.0);
  LocalGridOptions o = scanOptions();
  const LocalGrid plain = rayTraceScan2D(scan, o);
  EXPECT_EQ(countIn(plain.empty, -0.5, 1.0, 0.5, 5.0), 0);  // nothing known on the left
  o.scan2dUnknownSpaceFilled = true;
  ScanRayTracingStats s;
  const LocalGrid filled = rayTraceScan2D(scan, o, &s);
  EXPECT_EQ(s.unknownRaysFilled, 90);
  EXPECT_GT(countIn(filled.empty, -0.5, 3.0, 0.5, 4.0), 0);  // free up to the scan's 4 m
  EXPECT_EQ(countIn(filled.empty, -5, 4.11, 5, 10), 0);
  EXPECT_EQ(filled.obstacles.total(), plain.obstacles.total());
  EXPECT_EQ(countIn(filled.obstacles, -5, 0.1, 5, 10), 0);  // no obstacle on the empty side
}

TEST(LocalGridScan, NaNAndInfPointsAreDroppedWithAWarning) {
  cv::Mat data(1, 4, CV_32FC2);
  data.at<cv::Vec2f>(0) = cv::Vec2f(1.0f, 0.0f);
  data.at<cv::Vec2f>(1) = cv::Vec2f(std::numeric_limits<float>::quiet_NaN(), 0.0f);
  data.at<cv::Vec2f>(2) = cv::Vec2f(std::numeric_limits<float>::infinity(), 1.0f);
  data.at<cv::Vec2f>(3) = cv::Vec2f(0.0f, 1.0f);
  const LaserScan scan(data, 4, 0.0, 10.0, LaserScan::kXY);
  const LocalGridResult r = createLocalGrid(SensorData(scan), scanOptions());
  ASSERT_TRUE(r.success) << r.why;
  EXPECT_EQ(r.stats.invalidPoints, 2);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("NaN"), std::string::npos);
  EXPECT_EQ(r.grid.obstacles.total(), 2u);
}

TEST(LocalGridScan, AllInvalidScanFailsWithAReasonAndNoGrid) {
  cv::Mat data(1, 3, CV_32FC2, cv::Scalar(std::numeric_limits<float>::quiet_NaN(), 0.0f));
  const LaserScan scan(data, 3, 0.0, 10.0, LaserScan::kXY);
  const LocalGridResult r = createLocalGrid(SensorData(scan), scanOptions());
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.why.find("NaN"), std::string::npos) << r.why;
  EXPECT_TRUE(r.grid.isEmpty());
  EXPECT_EQ(r.grid.cellSize, 0.0f);
}

TEST(LocalGridScan, NoScanForScanSensorIsAClearFailure) {
  const LocalGridResult r = createLocalGrid(SensorData(), scanOptions());
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.why.find("no laser scan"), std::string::npos) << r.why;
}

TEST(LocalGridScan, CompressedOnlyScanAsksToUncompress) {
  SensorData d(LaserScan::fromRanges({1.0f, 1.0f}, 0.0, 0.1, 0.0, 5.0));
  d.compress();
  d.clearRaw();
  const LocalGridResult r = createLocalGrid(d, scanOptions());
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.why.find("uncompress"), std::string::npos) << r.why;
}

TEST(LocalGridScan, RayTracing3DScanIsRejectedByThe2DStage) {
  cv::Mat data(1, 1, CV_32FC3, cv::Scalar(1, 0, 0));
  EXPECT_THROW(rayTraceScan2D(LaserScan(data, 1, 0, 10, LaserScan::kXYZ), scanOptions()), FormatError);
}

TEST(LocalGridScan, ScanDecimationKeepsOneBeamInN) {
  const LaserScan scan = LaserScan::fromRanges(std::vector<float>(100, 2.0f), -0.5, 0.01, 0.0, 10.0);
  LocalGridOptions o = scanOptions();
  o.scanDecimation = 4;
  ScanRayTracingStats s;
  rayTraceScan2D(scan, o, &s);
  EXPECT_EQ(s.beams, 25);
}

namespace {

// A 16-ring lidar (+-15 deg, 1 deg azimuth steps) 0.75 m above the floor of a 20 x 16 m hall
// with a 2.7 m ceiling, as a 3D LaserScan in the sensor frame with its base -> sensor mounting.
LaserScan ringLidarInRoom() {
  const double height = 0.75, ceiling = 2.7, halfX = 10.0, halfY = 8.0;
  std::vector<cv::Vec3f> points;
  for (int ring = 0; ring < 16; ++ring) {
    const double elevation = (-15.0 + 2.0 * ring) * M_PI / 180.0;
    for (int step = 0; step < 360; ++step) {
      const double azimuth = step * M_PI / 180.0;
      const Eigen::Vector3d d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                              std::sin(elevation));
      double t = std::numeric_limits<double>::infinity();
      if (d.z() < 0) t = std::min(t, -height / d.z());
      if (d.z() > 0) t = std::min(t, (ceiling - height) / d.z());
      if (d.x() != 0) t = std::min(t, halfX / std::abs(d.x()));
      if (d.y() != 0) t = std::min(t, halfY / std::abs(d.y()));
      const Eigen::Vector3d p = t * d;
      points.emplace_back(float(p.x()), float(p.y()), float(p.z()));
    }
  }
  cv::Mat data(1, int(points.size()), CV_32FC3, points.data());
  return LaserScan(data.clone(), int(points.size()), 0.0, 30.0, LaserScan::kXYZ, Transform(0, 0, height, 0, 0, 0));
}

// Heights (z) of a cell matrix (N cells of 3 floats).
std::vector<float> heights(const cv::Mat& cells) {
  std::vector<float> z;
  const cv::Mat flat = cells.reshape(1, int(cells.total()));
  for (int i = 0; i < flat.rows; ++i) z.push_back(flat.at<float>(i, 2));
  return z;
}

}  // namespace

TEST(LocalGridScan, Lidar3DFloorIsGroundAndEachPointIsSegmentedOnce) {
  // A 3D scan alone goes through the cloud path: voxel filter, height crop, segmentation. Its
  // points used to be appended to the obstacles a second time, raw, after the segmentation:
  // every floor cell became an obstacle and the map had no free space.
  LocalGridOptions o = scanOptions();
  o.grid3D = true;
  o.normalsSegmentation = false;
  o.maxGroundHeight = 0.1f;
  o.maxObstacleHeight = 2.0f;
  const LocalGridResult r = createLocalGrid(SensorData(ringLidarInRoom()), o);
  ASSERT_TRUE(r.success) << r.why;
  EXPECT_EQ(r.source, "scan 3D");
  EXPECT_EQ(r.stats.groundPoints + r.stats.obstaclePoints, r.stats.voxelPoints - r.stats.heightCropped);
  const std::vector<float> ground = heights(r.grid.ground), obstacles = heights(r.grid.obstacles);
  ASSERT_GT(ground.size(), 100u);  // the floor rings, in the base frame (z ~ 0)
  ASSERT_GT(obstacles.size(), 100u);  // the walls between 0.1 and 2 m
  for (float z : ground) EXPECT_LE(std::abs(z), 0.1f);
  for (float z : obstacles) {
    EXPECT_GT(z, 0.1f);
    EXPECT_LE(z, 2.0f);  // the ceiling (2.7 m) was cropped
  }
  EXPECT_GT(r.stats.heightCropped, 0);
}

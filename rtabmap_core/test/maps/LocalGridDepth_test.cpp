// Local grids from depth images and stereo: segmentation of a floor with a box and a table,
// footprint removal, clustering, 2D / 3D outputs, ray tracing, bad input.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <random>
#include <set>

#include "common/TestData.h"
#include "maps/MapsTestUtil.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/LocalGridMaker.h"
#include "rtabmap_core/maps/LocalGridStages.h"

using namespace rtabmap;
using rtabmap::test::countIn;
using rtabmap::test::DepthScene;

namespace {

LocalGridOptions depthOptions() {
  LocalGridOptions o;  // Grid/* defaults: depth, normals segmentation, 5 cm, 3D
  o.depthDecimation = 2;
  return o;
}

SensorData sceneData() { return DepthScene::floorBoxTable().render(320, 240, 262.5, 1.0, 30.0 * M_PI / 180.0); }

}  // namespace

TEST(LocalGridDepth, FloorIsGroundBoxAndTableTopAreObstacles3D) {
  const LocalGridResult r = createLocalGrid(sceneData(), depthOptions());
  ASSERT_TRUE(r.success) << r.why;
  EXPECT_EQ(r.source, "depth");
  const LocalGrid& g = r.grid;
  EXPECT_EQ(g.obstacles.channels(), 4);  // x y z rgb: the scene has colour
  // The floor: ground, never obstacle (away from the objects' feet).
  EXPECT_GT(countIn(g.ground, 0.8, -0.3, 1.6, 0.3, -0.05, 0.05), 20);
  EXPECT_EQ(countIn(g.obstacles, 0.8, -0.3, 1.6, 0.3, -0.05, 0.05), 0);
  // The box (faces and top) is an obstacle; its top, though flat, is above the floor.
  EXPECT_GT(countIn(g.obstacles, 1.95, -0.85, 2.45, -0.35, 0.05, 0.55), 20);
  EXPECT_GT(countIn(g.obstacles, 1.95, -0.85, 2.45, -0.35, 0.45, 0.55), 5);
  EXPECT_EQ(countIn(g.ground, 1.95, -0.85, 2.45, -0.35, 0.1, 1.0), 0);
  // The table top: a flat surface at 0.72 m is an obstacle, not ground.
  EXPECT_GT(countIn(g.obstacles, 1.75, 0.25, 2.65, 1.15, 0.65, 0.8), 30);
  EXPECT_EQ(countIn(g.ground, 1.75, 0.25, 2.65, 1.15, 0.3, 1.0), 0);
  EXPECT_GE(r.stats.flatObstacleClusters, 2);  // table top and box top
  EXPECT_GT(r.stats.stageMs.count("segmentation"), 0u);
}

TEST(LocalGridDepth, FlatObstacleDetectionOffMakesTheTableTopGround) {
  LocalGridOptions o = depthOptions();
  o.flatObstacleDetected = false;
  const LocalGridResult r = createLocalGrid(sceneData(), o);
  ASSERT_TRUE(r.success) << r.why;
  EXPECT_GT(countIn(r.grid.ground, 1.75, 0.25, 2.65, 1.15, 0.65, 0.8), 30);
}

TEST(LocalGridDepth, ProjectionTo2DKeepsObstacleCellsAndGroundCells) {
  LocalGridOptions o = depthOptions();
  o.grid3D = false;
  const LocalGridResult r = createLocalGrid(sceneData(), o);
  ASSERT_TRUE(r.success) << r.why;
  const LocalGrid& g = r.grid;
  ASSERT_EQ(g.obstacles.type(), CV_32FC2);
  ASSERT_EQ(g.ground.type(), CV_32FC2);
  EXPECT_GT(countIn(g.obstacles, 1.95, -0.85, 2.45, -0.35), 10);   // box
  EXPECT_GT(countIn(g.obstacles, 1.75, 0.25, 2.65, 1.15), 30);     // table top
  EXPECT_GT(countIn(g.ground, 0.8, -0.3, 1.6, 0.3), 50);           // floor in front
  EXPECT_TRUE(g.empty.empty());
  // One point per cell, and never ground where there is an obstacle.
  const Cloud obstacles = cloudFromCells(g.obstacles), ground = cloudFromCells(g.ground);
  std::set<std::pair<int, int>> obstacleCells;
  for (const auto& p : obstacles.points) {
    EXPECT_TRUE(obstacleCells.insert({int(std::floor(p.x / 0.05f)), int(std::floor(p.y / 0.05f))}).second);
  }
  for (const auto& p : ground.points) {
    EXPECT_FALSE(obstacleCells.count({int(std::floor(p.x / 0.05f)), int(std::floor(p.y / 0.05f))}));
  }
}

TEST(LocalGridDepth, RayTracing2DFreesCellsBetweenTheCameraAndWhatItSees) {
  LocalGridOptions o = depthOptions();
  o.grid3D = false;
  o.rayTracing = true;
  const LocalGridResult r = createLocalGrid(sceneData(), o);
  ASSERT_TRUE(r.success) << r.why;
  // The floor nearest the robot is out of view (0 .. 0.7 m): ray tracing marks it free.
  EXPECT_GT(countIn(r.grid.empty, 0.0, -0.1, 0.6, 0.1), 8);
  EXPECT_EQ(countIn(r.grid.empty, 2.05, -0.75, 2.35, -0.45), 0);  // inside the box
}

TEST(LocalGridDepth, RayTracing3DFillsEmptyVoxelsInFrontOfObstaclesOnly) {
  LocalGridOptions o = depthOptions();
  o.rayTracing = true;
  const LocalGridResult r = createLocalGrid(sceneData(), o);
  ASSERT_TRUE(r.success) << r.why;
  const LocalGrid& g = r.grid;
  ASSERT_EQ(g.empty.type(), CV_32FC3);
  EXPECT_GT(countIn(g.empty, 1.0, -0.7, 1.8, -0.5, 0.1, 0.4), 10);  // air in front of the box
  EXPECT_EQ(countIn(g.empty, 2.05, -0.75, 2.35, -0.45, 0.05, 0.45), 0);  // inside the box
  EXPECT_EQ(countIn(g.empty, -10, -10, 10, 10, -5, -0.06), 0);  // nothing under the floor
  EXPECT_GT(r.stats.stageMs.count("ray tracing 3D"), 0u);
}

TEST(LocalGridDepth, HeightSegmentationSplitsAtMaxGroundHeight) {
  LocalGridOptions o = depthOptions();
  o.normalsSegmentation = false;
  o.maxGroundHeight = 0.05f;
  const LocalGridResult r = createLocalGrid(sceneData(), o);
  ASSERT_TRUE(r.success) << r.why;
  EXPECT_GT(countIn(r.grid.ground, 0.8, -0.3, 1.6, 0.3, -0.05, 0.05), 20);
  EXPECT_EQ(countIn(r.grid.ground, -10, -10, 10, 10, 0.06, 5), 0);
  EXPECT_GT(countIn(r.grid.obstacles, 1.75, 0.25, 2.65, 1.15, 0.65, 0.8), 30);
}

TEST(LocalGridDepth, MaxGroundHeightWithNormalsKeepsFlatSurfacesAboveItObstacles) {
  LocalGridOptions o = depthOptions();
  o.maxGroundHeight = 0.1f;
  const LocalGridResult r = createLocalGrid(sceneData(), o);
  ASSERT_TRUE(r.success) << r.why;
  EXPECT_GT(countIn(r.grid.obstacles, 1.75, 0.25, 2.65, 1.15, 0.65, 0.8), 30);
  EXPECT_EQ(countIn(r.grid.ground, -10, -10, 10, 10, 0.11, 5), 0);
}

TEST(LocalGridDepth, MaxObstacleHeightDropsWhatIsAbove) {
  LocalGridOptions o = depthOptions();
  o.maxObstacleHeight = 0.6f;
  const LocalGridResult r = createLocalGrid(sceneData(), o);
  ASSERT_TRUE(r.success) << r.why;
  EXPECT_EQ(countIn(r.grid.obstacles, -10, -10, 10, 10, 0.61, 5), 0);
  EXPECT_GT(r.stats.heightCropped, 0);
}

TEST(LocalGridDepth, FootprintRemovalDropsTheRobotsOwnPoints) {
  Cloud c;
  c.push_back({0.1f, 0.0f, 0.2f});   // the robot's bumper
  c.push_back({0.1f, 0.0f, 0.9f});   // above the robot (footprint height 0.5)
  c.push_back({0.5f, 0.0f, 0.2f});   // in front of it
  c.push_back({0.0f, 0.25f, 0.2f});  // beside it
  LocalGridOptions o;
  o.footprintLength = 0.4f;
  o.footprintWidth = 0.4f;
  o.footprintHeight = 0.5f;
  int removed = 0;
  const Cloud kept = removeFootprint(c, o, &removed);
  EXPECT_EQ(removed, 1);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_FLOAT_EQ(kept.points[0].z, 0.9f);
  o.footprintHeight = 0.0f;  // no height: the whole column
  EXPECT_EQ(removeFootprint(c, o).size(), 2u);
  o.footprintLength = 0.0f;
  o.footprintWidth = 0.0f;
  EXPECT_EQ(removeFootprint(c, o).size(), 4u);  // no footprint
}

TEST(LocalGridDepth, FootprintInThePipelineRemovesABoxAroundTheRobot) {
  // A box standing where the robot is (its own body seen by the camera) disappears.
  DepthScene s = DepthScene::floorBoxTable();
  s.boxes.push_back({{0.55, -0.2, 0.0}, {0.75, 0.2, 0.3}});
  const SensorData d = s.render(320, 240, 262.5, 1.0, 40.0 * M_PI / 180.0);
  LocalGridOptions o = depthOptions();
  const LocalGridResult with = createLocalGrid(d, o);
  ASSERT_TRUE(with.success) << with.why;
  EXPECT_GT(countIn(with.grid.obstacles, 0.5, -0.25, 0.8, 0.25), 5);
  o.footprintLength = 1.6f;
  o.footprintWidth = 0.6f;
  const LocalGridResult without = createLocalGrid(d, o);
  ASSERT_TRUE(without.success) << without.why;
  EXPECT_EQ(countIn(without.grid.obstacles, 0.5, -0.25, 0.8, 0.25), 0);
  EXPECT_GT(without.stats.footprintRemoved, 0);
}

TEST(LocalGridDepth, ClusteringDropsSmallObstacleClusters) {
  Cloud c;
  for (int i = 0; i < 20; ++i) c.push_back({1.0f + 0.02f * i, 0.0f, 0.3f});  // an object
  c.push_back({3.0f, 2.0f, 0.5f});  // a speck
  c.push_back({3.02f, 2.0f, 0.5f});
  ClusterStats s;
  const Cloud kept = clusterObstacles(c, 0.05f, 5, &s);
  EXPECT_EQ(kept.size(), 20u);
  EXPECT_EQ(s.kept, 1);
  EXPECT_EQ(s.dropped, 1);
  EXPECT_EQ(s.droppedPoints, 2);
  EXPECT_EQ(clusterObstacles(c, 0.05f, 1).size(), 22u);
}

TEST(LocalGridDepth, NoiseFilterNeedsNeighbours) {
  Cloud c;
  for (int i = 0; i < 10; ++i) c.push_back({0.01f * i, 0.0f, 0.0f});
  c.push_back({5.0f, 0.0f, 0.0f});
  int removed = 0;
  EXPECT_EQ(filterNoise(c, 0.05f, 3, &removed).size(), 10u);
  EXPECT_EQ(removed, 1);
}

TEST(LocalGridDepth, VoxelFilterKeepsOneCentroidPerVoxelAndAveragesColours) {
  Cloud c;
  c.push_back({0.01f, 0.01f, 0.01f}, {0, 0, 0});
  c.push_back({0.03f, 0.03f, 0.03f}, {200, 100, 50});
  c.push_back({0.26f, 0.0f, 0.0f}, {10, 10, 10});
  const Cloud v = voxelFilter(c, 0.05f);
  ASSERT_EQ(v.size(), 2u);
  ASSERT_TRUE(v.hasColors());
  bool found = false;
  for (size_t i = 0; i < v.size(); ++i) {
    if (v.points[i].x < 0.1f) {
      found = true;
      EXPECT_NEAR(v.points[i].x, 0.02f, 1e-5);
      EXPECT_NEAR(v.colors[i][0], 100, 1);
    }
  }
  EXPECT_TRUE(found);
}

TEST(LocalGridDepth, DepthFullOfZerosFailsWithAReason) {
  SensorData d = sceneData();
  d.setRGBDImage(d.imageRaw(), cv::Mat(240, 320, CV_16UC1, cv::Scalar(0)), d.cameraModels());
  const LocalGridResult r = createLocalGrid(d, depthOptions());
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.why.find("no valid pixel"), std::string::npos) << r.why;
  EXPECT_TRUE(r.grid.isEmpty());
}

TEST(LocalGridDepth, DepthOfInvalidMarkersAndNaNFails) {
  SensorData d = sceneData();
  d.setRGBDImage(d.imageRaw(), cv::Mat(240, 320, CV_32FC1, cv::Scalar(std::nanf(""))), d.cameraModels());
  EXPECT_FALSE(createLocalGrid(d, depthOptions()).success);
  d.setRGBDImage(d.imageRaw(), cv::Mat(240, 320, CV_16UC1, cv::Scalar(65535)), d.cameraModels());
  const LocalGridResult r = createLocalGrid(d, depthOptions());
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.why.find("no valid pixel"), std::string::npos) << r.why;
}

TEST(LocalGridDepth, EverythingOutOfRangeFailsNamingTheRange) {
  LocalGridOptions o = depthOptions();
  o.rangeMax = 0.3f;
  const LocalGridResult r = createLocalGrid(sceneData(), o);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.why.find("Grid/RangeMax"), std::string::npos) << r.why;
}

TEST(LocalGridDepth, NoDepthForDepthSensorIsAClearFailure) {
  const LocalGridResult r = createLocalGrid(SensorData(LaserScan::fromRanges({1.f}, 0, 0.1, 0, 5)), depthOptions());
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.why.find("depth"), std::string::npos) << r.why;
}

TEST(LocalGridDepth, BothSensorsAddScanPointsAsObstacles) {
  SensorData d = sceneData();
  // A wall segment seen only by the laser, 3 m ahead at 0.3 m height.
  std::vector<float> ranges(21, 3.0f);
  d.setLaserScan(LaserScan::fromRanges(ranges, -0.1, 0.01, 0.0, 10.0, Transform(0, 0, 0.3, 0, 0, 0)));
  LocalGridOptions o = depthOptions();
  o.sensor = LocalGridOptions::Sensor::kBoth;
  const LocalGridResult r = createLocalGrid(d, o);
  ASSERT_TRUE(r.success) << r.why;
  EXPECT_EQ(r.source, "depth+scan");
  EXPECT_GE(countIn(r.grid.obstacles, 2.9, -0.35, 3.1, 0.35, 0.25, 0.35), 5);
  // The camera's colours survive the laser's colourless points; those are white.
  ASSERT_EQ(r.grid.obstacles.channels(), 4);
  ASSERT_EQ(r.grid.ground.channels(), 4);
  int white = 0, red = 0;
  const float* p = r.grid.obstacles.ptr<float>();
  for (size_t i = 0; i < r.grid.obstacles.total(); ++i, p += 4) {
    const cv::Vec3b c = unpackRgb(p[3]);
    const bool laserWall = p[0] > 2.9f && p[0] < 3.1f && std::abs(p[1]) < 0.35f && p[2] > 0.25f && p[2] < 0.35f;
    if (laserWall) {
      EXPECT_EQ(c, cv::Vec3b(255, 255, 255)) << "laser point " << p[0] << " " << p[1] << " " << p[2];
      ++white;
    }
    if (c == cv::Vec3b(255, 0, 0)) ++red;  // the box (BGR 0 0 255 in the image)
  }
  EXPECT_GE(white, 5);
  EXPECT_GT(red, 10);
}

TEST(LocalGridDepth, DepthDecimationAndRoiReduceThePixelsRead) {
  DepthCloudStats full, cut;
  LocalGridOptions o = depthOptions();
  o.depthDecimation = 1;
  const SensorData d = sceneData();
  cloudFromDepth(d.depthOrRightRaw(), cv::Mat(), d.cameraModels(), o, &full);
  EXPECT_EQ(full.pixels, 320 * 240);
  o.depthDecimation = 4;
  o.depthRoiRatios = {0.25f, 0.25f, 0.5f, 0.0f};
  cloudFromDepth(d.depthOrRightRaw(), cv::Mat(), d.cameraModels(), o, &cut);
  EXPECT_EQ(cut.pixels, (160 / 4) * (120 / 4));
}

TEST(LocalGridDepth, StereoBlockMatchingGivesTheDepthOfATexturedPlane) {
  // A fronto-parallel textured plane at 2 m: right image = left shifted by the disparity.
  const double f = 400, baseline = 0.1, z = 2.0;
  const int disparity = static_cast<int>(std::lround(f * baseline / z));  // 20 px
  cv::Mat texture(240, 320 + disparity, CV_8UC1);
  cv::RNG rng(test::drawSeed(7));
  rng.fill(texture, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(texture, texture, cv::Size(3, 3), 0.8);
  // left(u) = texture(u), right(u) = texture(u + d): a point at left column u is at u - d on the
  // right, a positive disparity d.
  const cv::Mat left = texture(cv::Rect(0, 0, 320, 240)).clone();
  const cv::Mat right = texture(cv::Rect(disparity, 0, 320, 240)).clone();
  const StereoCameraModel model(f, f, 160, 120, baseline, CameraModel::opticalRotation(), cv::Size(320, 240));
  StereoBMOptions bm;
  bm.numDisparities = 64;
  const cv::Mat depth = depthFromStereo(left, right, model, bm);
  std::vector<float> valid;
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u)
      if (depth.at<float>(v, u) > 0) valid.push_back(depth.at<float>(v, u));
  ASSERT_GT(valid.size(), 240u * 320u / 4);
  std::nth_element(valid.begin(), valid.begin() + valid.size() / 2, valid.end());
  EXPECT_NEAR(valid[valid.size() / 2], z, 0.02);
  // The pipeline takes the pair like a depth image.
  SensorData d(left, right, model, 1);
  LocalGridOptions o = depthOptions();
  o.stereo = bm;
  const LocalGridResult r = createLocalGrid(d, o);
  ASSERT_TRUE(r.success) << r.why;
  EXPECT_EQ(r.source, "stereo");
  EXPECT_GT(countIn(r.grid.obstacles, 1.9, -2, 2.1, 2), 20);  // the plane, 2 m ahead
  StereoBMOptions bad = bm;
  bad.blockSize = 4;
  EXPECT_THROW(depthFromStereo(left, right, model, bad), ParameterError);
  EXPECT_THROW(depthFromStereo(left, right(cv::Rect(0, 0, 100, 100)), model, bm), FormatError);
}

TEST(LocalGridDepth, MapFrameProjectionLevelsATiltedRobot) {
  // The robot pitched 10 degrees nose down (on a ramp), the scene rendered in its tilted frame:
  // without levelling, the floor looks sloped; with the odometry's pitch, segmentation is done
  // level and the result comes back in the base frame.
  const Transform tilted(0, 0, 0, 0, 10.0 * M_PI / 180.0, 0);
  SensorData d = DepthScene::floorBoxTable().render(320, 240, 262.5, 1.0, 20.0 * M_PI / 180.0, tilted);
  // Express the camera in the tilted base: the renderer placed it at robotPose * local.
  d.setOdom(tilted, Eigen::Matrix<double, 6, 6>::Identity());
  LocalGridOptions o = depthOptions();
  o.mapFrameProjection = true;
  o.maxGroundHeight = 0.1f;  // height rule: meaningful only once levelled
  const LocalGridResult r = createLocalGrid(d, o);
  ASSERT_TRUE(r.success) << r.why;
  const Cloud ground = transformCloud(cloudFromCells(r.grid.ground), tilted);
  for (const auto& p : ground.points) EXPECT_LT(p.z, 0.11f);
  EXPECT_GT(ground.size(), 50u);
}

TEST(LocalGridDepth, BytesOfAGridAreReported) {
  const LocalGridResult r = createLocalGrid(sceneData(), depthOptions());
  ASSERT_TRUE(r.success);
  const LocalGridBytes b = localGridBytes(r.grid);
  EXPECT_EQ(b.raw, (r.grid.ground.total() + r.grid.obstacles.total()) * 16);
  EXPECT_GT(b.compressed, 0u);
  EXPECT_LT(b.compressed, b.raw + 200);
}

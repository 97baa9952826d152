// Ray casting in the 2.5D world and the analytic column renderer, on hand-built scenes whose
// geometry is known exactly.
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>

#include "SimTestUtil.h"
#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/sim/Renderer.h"
#include "rtabmap_core/sim/Simulator.h"

using namespace rtabmap::sim;
using rtabmap::sim::test::boxRoom;
using rtabmap::sim::test::material;

namespace {

// A pinhole camera of that size and focal length, its principal point at the image centre.
CameraIntrinsics intrinsics(int width, int height, double focal) {
  CameraIntrinsics k;
  k.width = width;
  k.height = height;
  k.fx = k.fy = focal;
  k.cx = (width - 1) / 2.0;
  k.cy = (height - 1) / 2.0;
  return k;
}

CameraIntrinsics smallIntrinsics() { return intrinsics(160, 120, 100.0); }

}  // namespace

TEST(SimWorld, RaysReportCrossingsInOrderAndStopAtTallSolids) {
  auto world = boxRoom(5, 4, 2.5, material(MaterialKind::kBrick, 1), material(MaterialKind::kPaint, 2), 64, 16, false);
  // A low box (0.4 m) and, beyond it, the far wall.
  world->addSolid({{2.0, 1.5}, {2.5, 1.5}, {2.5, 2.5}, {2.0, 2.5}}, 0.4f, SolidKind::kFurniture, {SurfaceMaterial()},
                  SurfaceMaterial(), "box");
  world->finalize();
  std::vector<RayHit> hits;
  ASSERT_TRUE(world->castRay({1.0, 2.0}, {1.0, 0.0}, 100.0, 2.5f, hits));
  ASSERT_EQ(hits.size(), 3u);
  EXPECT_NEAR(hits[0].t, 1.0, 1e-12);
  EXPECT_TRUE(hits[0].entering);
  EXPECT_NEAR(hits[1].t, 1.5, 1e-12);
  EXPECT_FALSE(hits[1].entering);
  EXPECT_NEAR(hits[2].t, 4.0, 1e-12);
  EXPECT_TRUE(hits[2].entering);
  // A beam at 0.25 m is blocked by the box.
  ASSERT_TRUE(world->castRay({1.0, 2.0}, {1.0, 0.0}, 100.0, 0.25f, hits));
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_NEAR(hits[0].t, 1.0, 1e-12);
  // t is in units of |dir|.
  ASSERT_TRUE(world->castRay({1.0, 2.0}, {2.0, 0.0}, 100.0, 2.5f, hits));
  EXPECT_NEAR(hits.back().t, 2.0, 1e-12);
  // Along a face's diagonal and from outside the world.
  EXPECT_TRUE(world->castRay({1.0, 1.0}, {1.0, 1.0}, 100.0, 2.5f, hits));
  EXPECT_FALSE(world->castRay({100.0, 100.0}, {1.0, 0.0}, 100.0, 2.5f, hits));
  EXPECT_TRUE(hits.empty());
  // Position along the face: the far wall's inner face runs from y = d down to y = 0 or up.
  world->castRay({1.0, 3.0}, {1.0, 0.0}, 100.0, 2.5f, hits);
  const Face& f = world->faces()[static_cast<size_t>(hits.back().face)];
  EXPECT_NEAR((f.a + hits.back().s * f.dir - Eigen::Vector2d(5.0, 3.0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(f.normal.x(), -1.0, 1e-12);  // outward from the wall: into the room
  EXPECT_NEAR(world->clearance({1.0, 2.0}), 1.0, 1e-12);
  EXPECT_TRUE(world->insideSolid({2.2, 2.0}));
  EXPECT_FALSE(world->insideSolid({2.2, 2.0}, 0.5f));
}

TEST(SimWorld, ClockwisePolygonsGetOutwardNormals) {
  World world(2.5);
  world.addSolid({{0, 0}, {0, 1}, {1, 1}, {1, 0}}, 1.0f, SolidKind::kFurniture, {SurfaceMaterial()}, SurfaceMaterial(), "cw");
  world.finalize();
  for (const Face& f : world.faces()) {
    const Eigen::Vector2d mid = 0.5 * (f.a + f.b);
    EXPECT_GT((mid + 0.1 * f.normal - Eigen::Vector2d(0.5, 0.5)).norm(), (mid - Eigen::Vector2d(0.5, 0.5)).norm());
  }
}

TEST(SimRenderer, DepthIsExactOnWallsFloorAndCeiling) {
  auto world = boxRoom(5, 4, 2.5, material(MaterialKind::kBrick, 1), material(MaterialKind::kConcrete, 2), 64, 16, false);
  world->addSolid({{2.5, 1.5}, {3.0, 1.5}, {3.0, 2.5}, {2.5, 2.5}}, 0.3f, SolidKind::kFurniture, {SurfaceMaterial()},
                  SurfaceMaterial(), "low box");
  world->finalize();
  const CameraIntrinsics k = smallIntrinsics();
  Renderer renderer(*world, k);
  const ViewPose pose{1.0, 2.0, 0.5, 0.0};
  cv::Mat bgr, depth;
  renderer.render(pose, bgr, &depth);
  ASSERT_EQ(bgr.size(), cv::Size(160, 120));
  ASSERT_EQ(depth.type(), CV_32FC1);
  // Every pixel back-projects onto a surface of the room.
  const rtabmap::CameraModel model(k.fx, k.fy, k.cx, k.cy);
  int onBoxTop = 0, onFarWall = 0;
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const float z = depth.at<float>(v, u);
      ASSERT_GT(z, 0.0f) << u << "," << v;  // a closed room: something everywhere
      double x, y, zz;
      ASSERT_TRUE(model.project(u, v, z, x, y, zz));
      // Optical (x right, y down, z forward) -> world for a camera facing +x at (1, 2, 0.5).
      const Eigen::Vector3d p(1.0 + zz, 2.0 - x, 0.5 - y);
      const bool farWall = std::fabs(p.x() - 5.0) < 1e-4;
      const bool side = std::fabs(p.y()) < 1e-4 || std::fabs(p.y() - 4.0) < 1e-4;
      const bool floor = std::fabs(p.z()) < 1e-4;
      const bool ceiling = std::fabs(p.z() - 2.5) < 1e-4;
      const bool boxFront = std::fabs(p.x() - 2.5) < 1e-4 && p.z() <= 0.3 + 1e-4 && p.y() >= 1.5 - 1e-4 && p.y() <= 2.5 + 1e-4;
      const bool boxTop = std::fabs(p.z() - 0.3) < 1e-4 && p.x() >= 2.5 - 1e-4 && p.x() <= 3.0 + 1e-4;
      onBoxTop += boxTop;
      onFarWall += farWall;
      EXPECT_TRUE(farWall || side || floor || ceiling || boxFront || boxTop) << "pixel " << u << "," << v << " -> " << p.transpose();
    }
  }
  EXPECT_GT(onBoxTop, 10);   // the box is lower than the eye: its top shows
  EXPECT_GT(onFarWall, 1000);
  // The far wall faces the camera: its depth is 4 m in every column.
  EXPECT_FLOAT_EQ(depth.at<float>(40, 80), 4.0f);
  // Bottom row: floor at fy * camZ / (v - cy).
  EXPECT_NEAR(depth.at<float>(119, 80), 100.0 * 0.5 / (119 - 59.5), 1e-5);
  // Top row: ceiling at fy * (2.5 - camZ) / (cy - v), nearer than the far wall straight ahead...
  EXPECT_NEAR(depth.at<float>(0, 80), 100.0 * 2.0 / 59.5, 1e-5);
  // ...but on the far left, the north wall (y = 4) comes first: the ray (1, 0.745) meets it at
  // depth 2 / 0.745.
  EXPECT_NEAR(depth.at<float>(0, 5), 2.0 / ((79.5 - 5) / 100.0), 1e-5);
}

TEST(SimRenderer, SameImageWhateverTheThreadCount) {
  const auto& building = rtabmap::sim::test::loopBuilding();
  Renderer renderer(*building.world, smallIntrinsics());
  const Eigen::Vector2d p = building.nav.nodes().front().position;
  const ViewPose pose{p.x(), p.y(), 0.5, 0.3};
  const int threads = cv::getNumThreads();
  cv::Mat a, b, da, db;
  cv::setNumThreads(1);
  renderer.render(pose, a, &da, 5);
  cv::setNumThreads(std::max(2, threads));
  renderer.render(pose, b, &db, 5);
  cv::setNumThreads(threads);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(da, db, cv::NORM_INF), 0.0);
}

TEST(SimRenderer, PixelNoiseIsOptionalAndKeyed) {
  auto world = boxRoom(5, 4, 2.5, material(MaterialKind::kPaint, 1), material(MaterialKind::kPaint, 2), 64, 16);
  RenderOptions noisy;
  noisy.noiseSigma = 3.0;
  Renderer clean(*world, smallIntrinsics()), withNoise(*world, smallIntrinsics(), noisy);
  const ViewPose pose{1.0, 2.0, 0.5, 0.0};
  cv::Mat a, b, c, d;
  clean.render(pose, a, nullptr, 1);
  withNoise.render(pose, b, nullptr, 1);
  withNoise.render(pose, c, nullptr, 1);
  withNoise.render(pose, d, nullptr, 2);
  EXPECT_EQ(cv::norm(b, c, cv::NORM_INF), 0.0);  // same key, same noise
  EXPECT_GT(cv::norm(b, d, cv::NORM_L1), 0.0);
  cv::Mat diff;
  cv::subtract(b, a, diff, cv::noArray(), CV_16S);
  cv::Scalar mean, sd;
  cv::meanStdDev(diff.reshape(1), mean, sd);
  EXPECT_NEAR(mean[0], 0.0, 0.2);
  EXPECT_NEAR(sd[0], 3.0, 0.6);
}

// One wall, half brick and half plain paint, seen square on: a corner detector finds many
// corners on the brick half and next to none on the paint.
TEST(SimRenderer, TexturedWallsGiveCornersPlainWallsDoNot) {
  auto world = std::make_unique<World>(2.6);
  const int brick = world->addTexture(makeMaterialTexture(material(MaterialKind::kBrick, 3, {60, 80, 160}), 512, 128));
  const int paint = world->addTexture(makeMaterialTexture(material(MaterialKind::kPaint, 4, {200, 210, 220}), 512, 128));
  SurfaceMaterial b, p;
  b.texture = brick;
  p.texture = paint;
  world->addSolid({{3.0, 0.0}, {3.1, 0.0}, {3.1, 3.0}, {3.0, 3.0}}, 2.6f, SolidKind::kWall, {b}, SurfaceMaterial(), "brick");
  world->addSolid({{3.0, -3.0}, {3.1, -3.0}, {3.1, 0.0}, {3.0, 0.0}}, 2.6f, SolidKind::kWall, {p}, SurfaceMaterial(), "paint");
  world->setRegions(cv::Mat::zeros(1, 1, CV_16UC1), -100, -100, 1000, {p}, {p});
  world->finalize();
  CameraIntrinsics k;  // 640 x 480, fx 525
  RenderOptions flat;
  flat.vignetting = false;
  Renderer renderer(*world, k, flat);
  cv::Mat bgr, depth, grey;
  renderer.render(ViewPose{0.0, 0.0, 1.2, 0.0}, bgr, &depth);
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(grey, corners, 2000, 0.01, 5);
  int left = 0, right = 0;
  for (const auto& c : corners) {
    if (std::fabs(c.x - k.cx) < 10) continue;  // the seam between the two walls
    if (c.x < k.cx) ++left;   // brick: y > 0 is on the left for a camera facing +x
    else ++right;
  }
  EXPECT_GT(left, 100);
  EXPECT_LT(right, 5);
}

// A long corridor of brick walls, floor tiles and a ceiling grid, materials 4 m to a tile. With
// plain periodic tiles, a camera moved one period along it sees the very same picture (what
// made appearance-based loop closure match places 4, 8, 12 m apart); with tile variants, the
// structure is the same but the details differ, while the same pose still renders identically.
TEST(SimRenderer, TileVariantsBreakThePeriodOfLargeSurfaces) {
  auto corridor = [](int variants) {
    auto world = std::make_unique<World>(2.6);
    const int brick = world->addTexture(makeMaterialTexture(material(MaterialKind::kBrick, 3, {60, 80, 160}), 128, 32, variants));
    const int tiles = world->addTexture(makeMaterialTexture(material(MaterialKind::kFloorTiles, 5, {120, 140, 150}), 128, 32, variants));
    const int grid = world->addTexture(makeMaterialTexture(material(MaterialKind::kCeilingTiles, 6, {220, 225, 225}), 128, 32, variants));
    SurfaceMaterial wall, floor, ceiling;
    wall.texture = brick;
    wall.variantKey = 11;
    floor.texture = tiles;
    ceiling.texture = grid;
    world->addSolid({{-60.0, 1.1}, {60.0, 1.1}, {60.0, 1.2}, {-60.0, 1.2}}, 2.6f, SolidKind::kWall, {wall}, SurfaceMaterial(), "wall");
    world->addSolid({{-60.0, -1.2}, {60.0, -1.2}, {60.0, -1.1}, {-60.0, -1.1}}, 2.6f, SolidKind::kWall, {wall}, SurfaceMaterial(), "wall");
    world->setRegions(cv::Mat::zeros(1, 1, CV_16UC1), -1000, -1000, 4000, {floor}, {ceiling});
    world->finalize();
    return world;
  };
  const CameraIntrinsics k = intrinsics(320, 240, 260.0);
  RenderOptions options;
  options.maxDepth = 15.0;  // the corridor's ends stay out of sight
  // Share of pixels whose grey level differs by more than 8 between two poses one period apart.
  auto changed = [&](const World& world, double x0, double x1) {
    const Renderer renderer(world, k, options);
    cv::Mat a, b, diff;
    renderer.render(ViewPose{x0, 0.3, 1.2, 0.2}, a, nullptr);
    renderer.render(ViewPose{x1, 0.3, 1.2, 0.2}, b, nullptr);
    cv::cvtColor(a, a, cv::COLOR_BGR2GRAY);
    cv::cvtColor(b, b, cv::COLOR_BGR2GRAY);
    cv::absdiff(a, b, diff);
    return cv::countNonZero(diff > 8) / static_cast<double>(k.width * k.height);
  };
  const auto periodic = corridor(1);
  const auto varied = corridor(4);
  EXPECT_EQ(changed(*varied, 2.0, 2.0), 0.0);  // same pose, same picture
  EXPECT_EQ(changed(*periodic, 2.0, 2.0), 0.0);
  for (const double x : {-7.0, 2.0, 13.0}) {
    SCOPED_TRACE(x);
    EXPECT_LT(changed(*periodic, x, x + 4.0), 0.005);  // one period on: the same picture
    EXPECT_LT(changed(*periodic, x, x + 8.0), 0.005);
    EXPECT_GT(changed(*varied, x, x + 4.0), 0.1);      // tile variants: another one
    EXPECT_GT(changed(*varied, x, x + 8.0), 0.1);
  }
}

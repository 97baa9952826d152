// The global OctoMap: insertion with ray tracing, ground / obstacle / free / frontier queries,
// agreement with the 2D grid, rebuild after moves, exports and message fields.
#include <gtest/gtest.h>

#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include <sstream>

#include "common/TestData.h"
#include "maps/MapsTestUtil.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/LocalGridMaker.h"
#include "rtabmap_core/maps/OccupancyGrid.h"
#include "rtabmap_core/maps/OctoMap.h"

using namespace rtabmap;
using rtabmap::test::DepthScene;

namespace {

LocalGrid sceneGrid(bool rayTracing, const Transform& robot = Transform::Identity()) {
  LocalGridOptions o;
  o.depthDecimation = 2;
  o.rayTracing = rayTracing;
  const LocalGridResult r =
      createLocalGrid(DepthScene::floorBoxTable().render(320, 240, 262.5, 1.0, 30.0 * M_PI / 180.0, robot), o);
  EXPECT_TRUE(r.success) << r.why;
  return r.grid;
}

// A cell of the local grid inside a box (the renderer samples surfaces sparsely at grazing
// angles: query voxels that hold a point).
Eigen::Vector3f pick(const cv::Mat& cells, float x0, float y0, float x1, float y1, float z0, float z1) {
  const Cloud c = cloudFromCells(cells);
  for (const auto& p : c.points) {
    if (p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1 && p.z >= z0 && p.z <= z1) return {p.x, p.y, p.z};
  }
  ADD_FAILURE() << "no cell in the box";
  return Eigen::Vector3f::Zero();
}
Eigen::Vector3f tableTop(const LocalGrid& g) { return pick(g.obstacles, 1.9f, 0.4f, 2.5f, 1.0f, 0.7f, 0.75f); }
Eigen::Vector3f boxFace(const LocalGrid& g) { return pick(g.obstacles, 2.0f, -0.7f, 2.05f, -0.5f, 0.1f, 0.4f); }
Eigen::Vector3f floorPoint(const LocalGrid& g) { return pick(g.ground, 1.0f, -0.3f, 1.5f, 0.3f, -0.05f, 0.05f); }

OctoMapOptions octoOptions(bool rayTracing = true) {
  OctoMapOptions o;
  o.rayTracing = rayTracing;
  return o;
}

}  // namespace

TEST(OctoMap, QueriesTellGroundObstaclesFreeAndUnknown) {
  OctoMap map(octoOptions());
  const LocalGrid g = sceneGrid(false);
  ASSERT_TRUE(map.addLocalGrid(1, g));
  const OctoMapUpdateSummary s = map.update({{1, Transform::Identity()}});
  EXPECT_EQ(s.nodesInserted, 1);
  EXPECT_GT(s.rayTracedPoints, 100);  // no empty voxels in the grid: rays were cast
  EXPECT_GT(s.freeVoxelUpdates, 1000);
  EXPECT_EQ(map.state(floorPoint(g)), VoxelState::kGround);
  EXPECT_EQ(map.state(boxFace(g)), VoxelState::kObstacle);
  EXPECT_EQ(map.state(tableTop(g)), VoxelState::kObstacle);  // flat, but above the floor
  EXPECT_EQ(map.state({1.5f, -0.6f, 0.25f}), VoxelState::kFree);        // air in front of the box
  EXPECT_EQ(map.state({2.2f, -0.6f, 0.25f}), VoxelState::kUnknown);     // inside the box
  EXPECT_EQ(map.state({-3.0f, 0.0f, 0.5f}), VoxelState::kUnknown);      // behind the camera
  EXPECT_TRUE(map.hasColor());
  const OctoMapCells c = map.cells();
  EXPECT_FLOAT_EQ(c.voxelSize, 0.05f);
  EXPECT_GT(c.ground.size(), 100u);
  EXPECT_GT(c.obstacles.size(), 100u);
  EXPECT_GT(c.empty.size(), c.obstacles.size());
  EXPECT_GT(c.frontiers.size(), 0u);
  EXPECT_LT(c.frontiers.size(), c.empty.size());
  ASSERT_TRUE(c.obstacles.hasColors());
  // The box is painted red by the renderer.
  int red = 0;
  for (size_t i = 0; i < c.obstacles.size(); ++i) red += c.obstacles.colors[i][0] > 200 && c.obstacles.colors[i][2] < 50;
  EXPECT_GT(red, static_cast<int>(c.obstacles.size()) / 2);
}

TEST(OctoMap, EmptyVoxelsOfTheLocalGridAreUsedInsteadOfRays) {
  OctoMap map(octoOptions());
  map.addLocalGrid(1, sceneGrid(true));
  const OctoMapUpdateSummary s = map.update({{1, Transform::Identity()}});
  EXPECT_EQ(s.rayTracedPoints, 0);
  EXPECT_GT(s.freeVoxelUpdates, 1000);
  EXPECT_EQ(map.state({1.5f, -0.6f, 0.25f}), VoxelState::kFree);
}

TEST(OctoMap, CoarserDepthsMergeVoxels) {
  OctoMap map(octoOptions());
  const LocalGrid g = sceneGrid(false);
  map.addLocalGrid(1, g);
  map.update({{1, Transform::Identity()}});
  const OctoMapCells fine = map.cells(16, false), coarse = map.cells(14, false);
  EXPECT_NEAR(coarse.voxelSize, 0.2f, 1e-6);
  EXPECT_LT(coarse.obstacles.size() * 4, fine.obstacles.size());
  EXPECT_GT(coarse.obstacles.size(), 0u);
  EXPECT_EQ(map.state(tableTop(g), 14), VoxelState::kObstacle);
}

TEST(OctoMap, ProjectionAgreesWithThe2DGridOnASimpleScene) {
  const LocalGrid g = sceneGrid(false);
  OctoMap octo(octoOptions(false));
  octo.addLocalGrid(1, g);
  octo.update({{1, Transform(0.3, -0.2, 0.4)}});
  GlobalGridOptions go;
  OccupancyGrid grid(go);
  grid.addLocalGrid(1, g);
  grid.update({{1, Transform(0.3, -0.2, 0.4)}});
  const GridMap a = octo.projection2D(), b = grid.map();
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  int agree = 0, known = 0;
  for (int r = 0; r < b.height(); ++r) {
    for (int c = 0; c < b.width(); ++c) {
      const int8_t vb = b.data.at<int8_t>(r, c);
      if (vb == GridMap::kUnknown) continue;
      const double x = b.originX + (c + 0.5) * b.resolution, y = b.originY + (r + 0.5) * b.resolution;
      ++known;
      agree += a.at(x, y) == vb;
    }
  }
  EXPECT_GT(known, 300);
  EXPECT_GE(agree, known * 97 / 100) << agree << " / " << known;
  EXPECT_NEAR(a.countOccupied(), b.countOccupied(), b.countOccupied() * 0.03);
}

TEST(OctoMap, ProjectionHeightBandIgnoresWhatIsAboveTheRobot) {
  OctoMap map(octoOptions(false));
  map.addLocalGrid(1, sceneGrid(false));
  map.update({{1, Transform::Identity()}});
  const GridMap low = map.projection2D(-0.1f, 0.6f);
  EXPECT_EQ(low.at(2.2, 0.7), GridMap::kFree);  // floor under the table: the top is above 0.6 m
  EXPECT_EQ(map.projection2D().at(2.2, 0.7), GridMap::kOccupied);
}

TEST(OctoMap, ItIsRebuiltWhenANodeMovesAndAppendedOtherwise) {
  OctoMap map(octoOptions(false));
  const LocalGrid g = sceneGrid(false);
  const Eigen::Vector3f top = tableTop(g);
  map.addLocalGrid(1, g);
  map.addLocalGrid(2, g);
  OctoMapUpdateSummary s = map.update({{1, Transform::Identity()}});
  EXPECT_FALSE(s.rebuilt);
  s = map.update({{1, Transform::Identity()}, {2, Transform(0, 5, 0)}});
  EXPECT_FALSE(s.rebuilt);
  EXPECT_EQ(s.nodesInserted, 1);
  EXPECT_EQ(map.state(top + Eigen::Vector3f(0, 5, 0)), VoxelState::kObstacle);
  s = map.update({{1, Transform::Identity()}, {2, Transform(0, 10, 0)}});
  EXPECT_TRUE(s.rebuilt);
  EXPECT_EQ(s.nodesMoved, 1);
  EXPECT_EQ(s.nodesInserted, 2);
  EXPECT_EQ(map.state(top + Eigen::Vector3f(0, 5, 0)), VoxelState::kUnknown);
  EXPECT_EQ(map.state(top + Eigen::Vector3f(0, 10, 0)), VoxelState::kObstacle);
  EXPECT_EQ(map.state(top), VoxelState::kObstacle);
  s = map.update({{2, Transform(0, 10, 0)}});
  EXPECT_TRUE(s.rebuilt);
  EXPECT_EQ(map.state(top), VoxelState::kUnknown);
}

TEST(OctoMap, FloodFillKeepsOnlyFreeSpaceConnectedToTheRobot) {
  OctoMapOptions o = octoOptions(false);
  o.floodFillDepth = 16;
  OctoMap map(o);
  // A free pocket far away, not connected to the node's view point.
  LocalGrid g = sceneGrid(true);
  Cloud empty = cloudFromCells(g.empty);
  const size_t connected = empty.size();
  for (int i = 0; i < 5; ++i) empty.push_back({20.0f + 0.05f * i, 20.0f, 1.0f});
  g.empty = cellsFromCloud(empty, false);
  map.addLocalGrid(1, g);
  map.update({{1, Transform::Identity()}});
  const OctoMapCells c = map.cells(0, false);
  EXPECT_GT(c.empty.size(), connected / 2);
  for (const auto& p : c.empty.points) EXPECT_LT(p.x, 19.0f);
}

TEST(OctoMap, BinaryAndFullFilesReadBackWithLiboctomap) {
  OctoMap map(octoOptions());
  const LocalGrid g = sceneGrid(false);
  const Eigen::Vector3f top = tableTop(g), face = boxFace(g);
  map.addLocalGrid(1, g);
  map.update({{1, Transform::Identity()}});
  test::TempDir dir("maps_octomap");
  ASSERT_TRUE(map.writeBinary(dir.file("map.bt")));
  ASSERT_TRUE(map.write(dir.file("map.ot")));
  octomap::OcTree bt(0.1);
  ASSERT_TRUE(bt.readBinary(dir.file("map.bt")));
  EXPECT_NEAR(bt.getResolution(), 0.05, 1e-8);
  const octomap::OcTreeNode* n = bt.search(top.x(), top.y(), top.z());
  ASSERT_NE(n, nullptr);
  EXPECT_TRUE(bt.isNodeOccupied(n));
  n = bt.search(1.5, -0.6, 0.25);
  ASSERT_NE(n, nullptr);
  EXPECT_FALSE(bt.isNodeOccupied(n));
  std::unique_ptr<octomap::AbstractOcTree> ot(octomap::AbstractOcTree::read(dir.file("map.ot")));
  ASSERT_NE(ot, nullptr);
  auto* color = dynamic_cast<octomap::ColorOcTree*>(ot.get());
  ASSERT_NE(color, nullptr);
  const octomap::ColorOcTreeNode* cn = color->search(face.x(), face.y(), face.z());
  ASSERT_NE(cn, nullptr);
  EXPECT_GT(cn->getColor().r, 200);  // the red box
  EXPECT_EQ(color->getNumLeafNodes(), map.leafCount());
}

TEST(OctoMap, MessageFieldsAreOctomapMsgsCompatible) {
  OctoMap map(octoOptions());
  const LocalGrid g = sceneGrid(false);
  const Eigen::Vector3f top = tableTop(g);
  map.addLocalGrid(1, g);
  map.update({{1, Transform::Identity()}});
  const OctoMapMessage bin = map.toMessage(true), full = map.toMessage(false);
  EXPECT_TRUE(bin.binary);
  EXPECT_EQ(bin.id, "OcTree");
  EXPECT_NEAR(bin.resolution, 0.05, 1e-8);  // Grid/CellSize is a float
  EXPECT_FALSE(full.binary);
  EXPECT_EQ(full.id, "ColorOcTree");
  EXPECT_GT(full.data.size(), bin.data.size());  // colours and log-odds vs 2 bits per child
  // The binary payload is what OcTree::readBinaryData reads (octomap_msgs::binaryMsgToMap).
  octomap::OcTree tree(bin.resolution);
  std::stringstream s(std::string(bin.data.begin(), bin.data.end()));
  tree.readBinaryData(s);
  EXPECT_EQ(tree.getNumLeafNodes(), map.leafCount());
  const octomap::OcTreeNode* n = tree.search(top.x(), top.y(), top.z());
  ASSERT_NE(n, nullptr);
  EXPECT_TRUE(tree.isNodeOccupied(n));
}

TEST(OctoMap, BadInputIsRefusedAndEmptyMapsAreNotWritten) {
  OctoMap map(octoOptions());
  std::string why;
  EXPECT_FALSE(map.addLocalGrid(1, LocalGrid(), &why));
  EXPECT_NE(why.find("empty"), std::string::npos);
  LocalGrid g = sceneGrid(false);
  g.cellSize = 0.1f;
  EXPECT_FALSE(map.addLocalGrid(1, g, &why));
  EXPECT_NE(why.find("Grid/CellSize"), std::string::npos);
  EXPECT_TRUE(map.empty());
  test::TempDir dir("maps_octomap_bad");
  EXPECT_FALSE(map.writeBinary(dir.file("empty.bt")));
  OctoMapOptions o;
  o.treeDepth = 17;
  EXPECT_THROW(OctoMap bad(o), ParameterError);
  o = OctoMapOptions();
  o.cellSize = 0.0f;
  try {
    OctoMap bad(o);
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("Grid/CellSize"), std::string::npos);
  }
  EXPECT_EQ(OctoMapOptions::fromParameters({{"GridGlobal/OctoMapTreeDepth", "15"}}).treeDepth, 15);
}

// The global 2D occupancy grid: log-odds model, incremental vs full vs region re-assembly,
// moved nodes, footprint, MinSize, nav_msgs layout, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/TestData.h"
#include "maps/MapsTestUtil.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/LocalGridMaker.h"
#include "rtabmap_core/maps/LocalGridStages.h"
#include "rtabmap_core/maps/OccupancyGrid.h"

using namespace rtabmap;
using Path = GridUpdateSummary::Path;

namespace {

struct ScanRun {
  std::map<int, Transform> poses;
  std::map<int, LocalGrid> grids;
};

// A robot driving down a 20 m x 3 m corridor with pillars, one node every 0.5 m.
ScanRun corridorRun(int nodes, float cellSize = 0.05f) {
  test::World2D world = test::World2D::room(0, 0, 20, 3);
  for (int i = 0; i < 6; ++i) world.boxes.push_back({{2.0 + 3.0 * i, 2.2, -1}, {2.4 + 3.0 * i, 2.6, 1}});
  LocalGridOptions o;
  o.cellSize = cellSize;
  o.rangeMax = 0.0f;
  ScanRun run;
  for (int i = 0; i < nodes; ++i) {
    const Transform pose(1.0 + 0.5 * i, 1.2 + 0.1 * std::sin(i), 0.3 * std::sin(0.7 * i));
    run.poses[i + 1] = pose;
    run.grids[i + 1] = rayTraceScan2D(test::simulateScan(world, pose, 181, M_PI, 8.0), o);
  }
  return run;
}

GlobalGridOptions options(float cellSize = 0.05f) {
  GlobalGridOptions o;
  o.cellSize = cellSize;
  return o;
}

void expectSameMap(const GridMap& a, const GridMap& b) {
  ASSERT_FALSE(a.empty());
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  EXPECT_DOUBLE_EQ(a.originX, b.originX);
  EXPECT_DOUBLE_EQ(a.originY, b.originY);
  EXPECT_EQ(cv::countNonZero(a.data != b.data), 0);
}

LocalGrid handGrid(std::vector<cv::Vec2f> obstacles, std::vector<cv::Vec2f> free, float c = 0.05f) {
  LocalGrid g;
  g.cellSize = c;
  if (!obstacles.empty()) g.obstacles = cv::Mat(obstacles, true).reshape(2, 1);
  if (!free.empty()) g.ground = cv::Mat(free, true).reshape(2, 1);
  return g;
}

std::map<int, Transform> shifted(const std::map<int, Transform>& poses, const Transform& t) {
  std::map<int, Transform> out;
  for (const auto& [id, p] : poses) out[id] = t * p;
  return out;
}

// Drives the run into both grids node by node, `evicting` keeping a Working Memory of its last
// `wm` nodes (the older ones are evicted); returns the graph of every node.
std::map<int, Transform> appendEvictingOld(const ScanRun& run, OccupancyGrid& inRam, OccupancyGrid& evicting,
                                           int wm = 10) {
  std::map<int, Transform> graph;
  for (const auto& [id, pose] : run.poses) {
    EXPECT_TRUE(inRam.addLocalGrid(id, run.grids.at(id)));
    EXPECT_TRUE(evicting.addLocalGrid(id, run.grids.at(id)));
    graph[id] = pose;
    inRam.update(graph);
    evicting.update(graph);
    if (id > wm) {
      EXPECT_TRUE(evicting.evictLocalGrid(id - wm));
    }
  }
  return graph;
}

}  // namespace

TEST(OccupancyGrid, IncrementalAssemblyEqualsFullAndRegionReassembly) {
  const ScanRun run = corridorRun(30);
  OccupancyGrid incremental(options());
  std::map<int, Transform> graph;
  for (const auto& [id, pose] : run.poses) {
    ASSERT_TRUE(incremental.addLocalGrid(id, run.grids.at(id)));
    graph[id] = pose;
    const GridUpdateSummary s = incremental.update(graph);
    EXPECT_EQ(s.path, Path::kIncremental);
    EXPECT_EQ(s.nodesAdded, 1);
  }
  // The same nodes first assembled at wrong poses, then re-assembled at the right ones.
  for (Path path : {Path::kFull, Path::kRegion}) {
    OccupancyGrid grid(options());
    for (const auto& [id, g] : run.grids) grid.addLocalGrid(id, g);
    grid.update(shifted(run.poses, Transform(0.7, -0.3, 0.2)));
    grid.forceNextPath(path);
    const GridUpdateSummary s = grid.update(run.poses);
    EXPECT_EQ(s.path, path);
    EXPECT_EQ(s.nodesMoved, 30);
    SCOPED_TRACE(pathName(path));
    expectSameMap(incremental.map(), grid.map());
  }
  const GridMap m = incremental.map();
  EXPECT_GT(m.countOccupied(), 500);
  EXPECT_GT(m.countFree(), 5000);
}

TEST(OccupancyGrid, MovingOneNodeMovesItsCellsAndTheRegionPathStaysExact) {
  const ScanRun run = corridorRun(30);
  OccupancyGrid grid(options());
  for (const auto& [id, g] : run.grids) grid.addLocalGrid(id, g);
  grid.update(run.poses);
  // Optimisation moves the last three nodes by 0.4 m sideways.
  std::map<int, Transform> moved = run.poses;
  for (int id = 28; id <= 30; ++id) moved[id] = Transform(0, 0.4, 0) * moved[id];
  const GridUpdateSummary s = grid.update(moved);
  EXPECT_EQ(s.nodesMoved, 3);
  EXPECT_EQ(s.path, Path::kRegion) << s.why;  // a small change: the region path is cheaper
  EXPECT_LT(s.nodesReplayed, 30);
  EXPECT_LT(s.estimatedRegionUnits, s.estimatedFullUnits);
  OccupancyGrid fresh(options());
  for (const auto& [id, g] : run.grids) fresh.addLocalGrid(id, g);
  fresh.update(moved);
  expectSameMap(fresh.map(), grid.map());
}

TEST(OccupancyGrid, ASingleNodesObstacleFollowsItsPose) {
  OccupancyGrid grid(options());
  ASSERT_TRUE(grid.addLocalGrid(1, handGrid({{2.02f, 0.01f}}, {{1.0f, 0.0f}})));
  grid.update({{1, Transform::Identity()}});
  EXPECT_EQ(grid.map().at(2.02, 0.01), GridMap::kOccupied);
  const GridUpdateSummary s = grid.update({{1, Transform(1.0, 0.0, 0.0)}});
  EXPECT_EQ(s.nodesMoved, 1);
  const GridMap m = grid.map();
  EXPECT_EQ(m.at(3.02, 0.01), GridMap::kOccupied);
  EXPECT_EQ(m.at(2.02, 0.01), GridMap::kFree);  // its free cell moved to 2.0
  EXPECT_EQ(m.countOccupied(), 1);
  // A rotation about the node moves far cells: 90 degrees puts the obstacle on +y.
  grid.update({{1, Transform(0.0, 0.0, M_PI / 2)}});
  EXPECT_EQ(grid.map().at(-0.01, 2.02), GridMap::kOccupied);
  EXPECT_EQ(grid.map().countOccupied(), 1);
}

TEST(OccupancyGrid, SmallPoseChangesBelowUpdateErrorKeepTheMap) {
  OccupancyGrid grid(options());
  grid.addLocalGrid(1, handGrid({{2.0f, 0.0f}}, {}));
  grid.update({{1, Transform::Identity()}});
  const GridUpdateSummary s = grid.update({{1, Transform(0.001, 0.0, 0.0)}});
  EXPECT_EQ(s.path, Path::kNone);
  EXPECT_EQ(s.nodesMoved, 0);
  EXPECT_DOUBLE_EQ(grid.assembledPoses().at(1).x(), 0.0);  // still at the pose it was assembled at
}

// Hours of mapping: thousands of nodes in the graph, most of them (Long-Term Memory) never
// moving again. An update that only appends must not rebuild the whole graph's bookkeeping
// (Map_assembling grew 2 -> 95 ms over the soak); its map stays the full assembly's, also with
// nodes nudged below UpdateError, nodes without a grid, and a removal or an insertion between.
TEST(OccupancyGrid, AppendOnlyUpdatesAreIncrementalAndExact) {
  const ScanRun run = corridorRun(36);
  OccupancyGrid grid(options());
  std::map<int, Transform> graph;
  for (const auto& [id, pose] : run.poses) {
    if (id % 7 != 0) {
      ASSERT_TRUE(grid.addLocalGrid(id, run.grids.at(id)));  // every 7th: no grid
    }
    // Earlier nodes nudged by 2 mm (below GridGlobal/UpdateError 1 cm): they stay where they are.
    for (auto& [other, p] : graph) p = Transform(0.002 * ((id + other) % 2), 0.0, 0.0) * run.poses.at(other);
    graph[id] = pose;
    if (id == 20) graph.erase(3);  // a node leaves the graph: not append-only
    const GridUpdateSummary s = grid.update(graph);
    if (id == 20) {
      EXPECT_EQ(s.nodesRemoved, 1);
      continue;
    }
    EXPECT_EQ(s.path, id % 7 ? Path::kIncremental : Path::kNone) << id << ": " << s.why;
    EXPECT_EQ(s.nodesAdded, id % 7 ? 1 : 0);
    EXPECT_EQ(s.nodesMoved, 0);
    EXPECT_EQ(s.nodesWithoutGrid, id / 7);
    EXPECT_EQ(s.nodesInGraph, s.nodesAssembled);
    EXPECT_EQ(size_t(s.nodesAssembled), grid.assembledPoses().size());
  }
  EXPECT_DOUBLE_EQ(grid.assembledPoses().at(1).x(), run.poses.at(1).x());  // assembled where it was
  // A grid that arrives late for a node before the last one: inserted by a re-assembly.
  ASSERT_TRUE(grid.addLocalGrid(14, run.grids.at(14)));
  const GridUpdateSummary late = grid.update(graph);
  EXPECT_EQ(late.nodesAdded, 0);
  EXPECT_NE(late.path, Path::kIncremental);
  std::map<int, Transform> assembled = grid.assembledPoses();
  OccupancyGrid fresh(options());
  for (const auto& [id, pose] : assembled) fresh.addLocalGrid(id, run.grids.at(id));
  fresh.update(assembled);
  expectSameMap(fresh.map(), grid.map());
}

TEST(OccupancyGrid, LogOddsClampingLetsACellChangeItsMind) {
  const GlobalGridOptions o = options();
  OccupancyGrid grid(o);
  std::map<int, Transform> graph;
  int id = 0;
  auto observe = [&](bool occupied) {
    ++id;
    grid.addLocalGrid(id, occupied ? handGrid({{1.02f, 0.02f}}, {}) : handGrid({}, {{1.02f, 0.02f}}));
    graph[id] = Transform::Identity();
    grid.update(graph);
    return grid.probability(1.02, 0.02);
  };
  EXPECT_NEAR(observe(true), o.probHit, 1e-3);  // first observation: the sensor model (log-odds in 1/1000)
  for (int i = 0; i < 20; ++i) observe(true);
  EXPECT_NEAR(grid.probability(1.02, 0.02), o.probClampingMax, 1e-3);  // clamped
  // From the clamp, logit(0.971) / -logit(0.4) = 8.7 misses bring it to free, not 20.
  // The grid keeps log-odds in thousandths.
  const float lMax = std::round(1000 * std::log(o.probClampingMax / (1 - o.probClampingMax))) / 1000;
  const float lMiss = std::round(1000 * std::log(o.probMiss / (1 - o.probMiss))) / 1000;
  const int needed = static_cast<int>(std::ceil(lMax / -lMiss + 1e-6));
  for (int i = 0; i < needed - 1; ++i) observe(false);
  EXPECT_EQ(grid.map().at(1.02, 0.02), GridMap::kOccupied);
  observe(false);
  EXPECT_EQ(grid.map().at(1.02, 0.02), GridMap::kFree);
  EXPECT_NEAR(grid.probability(1.02, 0.02), 1 / (1 + std::exp(-(lMax + needed * lMiss))), 1e-5);
}

TEST(OccupancyGrid, WithinOneNodeObstaclesWinOverItsFreeCells) {
  OccupancyGrid grid(options());
  grid.addLocalGrid(1, handGrid({{1.02f, 0.02f}}, {{1.03f, 0.03f}, {1.5f, 0.0f}}));
  grid.update({{1, Transform::Identity()}});
  EXPECT_EQ(grid.map().at(1.02, 0.02), GridMap::kOccupied);
  EXPECT_NEAR(grid.probability(1.02, 0.02), 0.7f, 1e-3);
}

TEST(OccupancyGrid, NavMsgsLayoutRowZeroIsTheLowestY) {
  OccupancyGrid grid(options());
  grid.addLocalGrid(1, handGrid({{1.02f, -0.48f}}, {{0.52f, 0.77f}}));
  grid.update({{1, Transform::Identity()}});
  const GridMap m = grid.map();
  EXPECT_FLOAT_EQ(m.resolution, 0.05f);
  // The bounds are exactly the known cells: obstacle at the lowest row, free at the top row.
  EXPECT_EQ(m.height(), 26);
  EXPECT_EQ(m.width(), 11);
  EXPECT_NEAR(m.originX, 0.50, 1e-6);  // 10 cells of the float resolution
  EXPECT_NEAR(m.originY, -0.50, 1e-6);
  EXPECT_EQ(m.data.at<int8_t>(0, 10), GridMap::kOccupied);
  EXPECT_EQ(m.data.at<int8_t>(25, 0), GridMap::kFree);
  EXPECT_EQ(m.data.at<int8_t>(10, 5), GridMap::kUnknown);
  EXPECT_EQ(m.countFree() + m.countOccupied() + m.countUnknown(), 26 * 11);
}

TEST(OccupancyGrid, MinSizePadsTheMapEvenly) {
  GlobalGridOptions o = options();
  o.minSize = 2.0f;
  OccupancyGrid grid(o);
  grid.addLocalGrid(1, handGrid({{0.02f, 0.02f}}, {}));
  grid.update({{1, Transform::Identity()}});
  const GridMap m = grid.map();
  EXPECT_EQ(m.width(), 40);
  EXPECT_EQ(m.height(), 40);
  EXPECT_EQ(m.countOccupied(), 1);
  EXPECT_EQ(m.countUnknown(), 40 * 40 - 1);
  EXPECT_EQ(m.at(0.02, 0.02), GridMap::kOccupied);
}

TEST(OccupancyGrid, FootprintClearsObstaclesWhereTheRobotHasBeen) {
  GlobalGridOptions o = options();
  o.footprintRadius = 0.3f;
  OccupancyGrid grid(o);
  // Node 1 sees an obstacle (a person) where node 2 later stands.
  grid.addLocalGrid(1, handGrid({{1.02f, 0.02f}, {3.02f, 0.02f}}, {}));
  grid.addLocalGrid(2, handGrid({{2.02f, 0.02f}}, {}));
  grid.update({{1, Transform::Identity()}, {2, Transform(1.0, 0.0, 0.0)}});
  GridMap m = grid.map();
  EXPECT_EQ(m.at(1.02, 0.02), GridMap::kFree);
  EXPECT_EQ(m.at(1.22, 0.02), GridMap::kFree);  // within the radius, unknown before: free now
  EXPECT_EQ(m.at(3.02, 0.02), GridMap::kOccupied);
  EXPECT_EQ(m.at(0.02, 0.02), GridMap::kFree);  // node 1's own footprint
  // Moving node 2 away moves its footprint too.
  grid.update({{1, Transform::Identity()}, {2, Transform(5.0, 5.0, 0.0)}});
  m = grid.map();
  EXPECT_EQ(m.at(1.02, 0.02), GridMap::kOccupied);
  EXPECT_EQ(m.at(5.02, 5.02), GridMap::kFree);
}

TEST(OccupancyGrid, ErosionRemovesIsolatedObstacleCells) {
  GlobalGridOptions o = options();
  o.eroded = true;
  OccupancyGrid grid(o);
  std::vector<cv::Vec2f> free;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) free.emplace_back(0.025f + 0.05f * i, 0.025f + 0.05f * j);
  grid.addLocalGrid(1, handGrid({{0.225f, 0.225f}, {0.025f, 0.475f}, {0.075f, 0.475f}}, free));
  grid.update({{1, Transform::Identity()}});
  const GridMap m = grid.map();
  EXPECT_EQ(m.at(0.225, 0.225), GridMap::kFree);     // alone: a speck
  EXPECT_EQ(m.at(0.025, 0.475), GridMap::kOccupied);  // part of a wall
}

TEST(OccupancyGrid, NodesLeavingTheGraphLeaveTheMap) {
  OccupancyGrid grid(options());
  grid.addLocalGrid(1, handGrid({{1.0f, 0.0f}}, {}));
  grid.addLocalGrid(2, handGrid({{0.0f, 1.0f}}, {}));
  grid.update({{1, Transform::Identity()}, {2, Transform::Identity()}});
  EXPECT_EQ(grid.map().countOccupied(), 2);
  const GridUpdateSummary s = grid.update({{2, Transform::Identity()}});
  EXPECT_EQ(s.nodesRemoved, 1);
  EXPECT_EQ(grid.map().countOccupied(), 1);
  EXPECT_EQ(grid.map().at(1.0, 0.0), GridMap::kUnknown);
}

TEST(OccupancyGrid, MaxNodesKeepsTheNewestAndAltitudeDeltaOneFloor) {
  GlobalGridOptions o = options();
  o.maxNodes = 2;
  OccupancyGrid grid(o);
  for (int id = 1; id <= 3; ++id) grid.addLocalGrid(id, handGrid({{float(id), 0.0f}}, {}));
  std::map<int, Transform> graph{{1, Transform::Identity()}, {2, Transform::Identity()}, {3, Transform::Identity()}};
  grid.update(graph);
  EXPECT_EQ(grid.map().at(1.0, 0.0), GridMap::kUnknown);
  EXPECT_EQ(grid.map().countOccupied(), 2);

  GlobalGridOptions a = options();
  a.altitudeDelta = 1.0f;
  OccupancyGrid floors(a);
  for (int id = 1; id <= 3; ++id) floors.addLocalGrid(id, handGrid({{float(id), 0.0f}}, {}));
  floors.update({{1, Transform(0, 0, 0, 0, 0, 0)}, {2, Transform(0, 0, 3, 0, 0, 0)}, {3, Transform(0, 0, 3.2, 0, 0, 0)}});
  EXPECT_EQ(floors.map().countOccupied(), 2);  // node 1 is on the floor below
}

TEST(OccupancyGrid, OutOfOrderAndReplacedNodesGiveTheFullMap) {
  const ScanRun run = corridorRun(12);
  OccupancyGrid grid(options());
  std::map<int, Transform> graph;
  for (int id : {1, 2, 3, 7, 8, 9, 10, 11, 12}) {
    grid.addLocalGrid(id, run.grids.at(id));
    graph[id] = run.poses.at(id);
  }
  grid.update(graph);
  for (int id : {4, 5, 6}) {  // retrieved from long-term memory later
    grid.addLocalGrid(id, run.grids.at(id));
    graph[id] = run.poses.at(id);
  }
  const GridUpdateSummary s = grid.update(graph);
  EXPECT_NE(s.path, Path::kIncremental);
  grid.addLocalGrid(5, run.grids.at(9));  // a node's grid recomputed (e.g. new parameters)
  grid.update(graph);

  OccupancyGrid fresh(options());
  for (const auto& [id, g] : run.grids) fresh.addLocalGrid(id, id == 5 ? run.grids.at(9) : g);
  fresh.update(graph);
  expectSameMap(fresh.map(), grid.map());
}

TEST(OccupancyGrid, TheCostModelLearnsFromMeasuredPaths) {
  const ScanRun run = corridorRun(40);
  OccupancyGrid grid(options());
  for (const auto& [id, g] : run.grids) grid.addLocalGrid(id, g);
  grid.update(run.poses);
  std::mt19937 rng(test::drawSeed(3));
  std::normal_distribution<double> noise(0.0, 0.05);
  // A node moved by no more than GridGlobal/UpdateError keeps its cells where they are (by
  // design), and the fresh map below would differ there: each node is moved by more than that
  // from where the grid has it, redrawn otherwise (1-2% of the moves at this noise: a few of the
  // 240 on 16 of test draws 1..20, none on draw 0).
  std::map<int, Transform> assembled = run.poses;
  for (int k = 0; k < 6; ++k) {
    std::map<int, Transform> moved;
    for (const auto& [id, p] : run.poses) {
      do {
        moved[id] = Transform{noise(rng), noise(rng), 0.0} * p;  // braces: drawn in order
      } while ((moved[id].translation() - assembled.at(id).translation()).norm() <= options().updateError);
    }
    assembled = moved;
    const GridUpdateSummary s = grid.update(moved);
    EXPECT_NE(s.path, Path::kIncremental);
    EXPECT_EQ(s.nodesMoved, 40);
    EXPECT_GT(s.estimatedFullUnits, 0.0);
    EXPECT_FALSE(s.why.empty());
    OccupancyGrid fresh(options());
    for (const auto& [id, g] : run.grids) fresh.addLocalGrid(id, g);
    fresh.update(moved);
    expectSameMap(fresh.map(), grid.map());
  }
}

TEST(OccupancyGrid, FullUpdateFalseAlwaysTakesTheRegionPath) {
  const ScanRun run = corridorRun(10);
  GlobalGridOptions o = options();
  o.fullUpdate = false;
  OccupancyGrid grid(o);
  for (const auto& [id, g] : run.grids) grid.addLocalGrid(id, g);
  grid.update(run.poses);
  EXPECT_EQ(grid.update(shifted(run.poses, Transform(1, 1, 0.3))).path, Path::kRegion);
}

TEST(OccupancyGrid, BadGridsAreRefusedWithAReason) {
  OccupancyGrid grid(options());
  std::string why;
  EXPECT_FALSE(grid.addLocalGrid(1, LocalGrid(), &why));
  EXPECT_NE(why.find("empty"), std::string::npos) << why;
  EXPECT_FALSE(grid.addLocalGrid(2, handGrid({{1, 1}}, {}, 0.1f), &why));
  EXPECT_NE(why.find("Grid/CellSize"), std::string::npos) << why;
  EXPECT_FALSE(grid.addLocalGrid(3, handGrid({{std::nanf(""), 1}}, {}), &why));
  EXPECT_NE(why.find("NaN"), std::string::npos) << why;
  LocalGrid wrongType;
  wrongType.cellSize = 0.05f;
  wrongType.obstacles = cv::Mat(1, 3, CV_8UC1, cv::Scalar(1));
  EXPECT_FALSE(grid.addLocalGrid(4, wrongType, &why));
  EXPECT_EQ(grid.cachedNodes(), 0u);
  // Poses without grids, null or non-finite poses add nothing, and say so.
  const GridUpdateSummary s = grid.update({{1, Transform::Identity()}, {9, Transform()}});
  EXPECT_EQ(s.nodesWithoutGrid, 1);
  EXPECT_TRUE(grid.map().empty());
}

TEST(OccupancyGrid, InvalidOptionsAreParameterErrorsNamingTheKey) {
  for (float c : {0.0f, -0.05f}) {
    GlobalGridOptions o;
    o.cellSize = c;
    std::string why;
    EXPECT_FALSE(o.IsValid(&why));
    EXPECT_NE(why.find("Grid/CellSize"), std::string::npos);
    try {
      OccupancyGrid grid(o);
      FAIL() << "cell size " << c << " accepted";
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find("Grid/CellSize"), std::string::npos) << e.what();
    }
  }
  GlobalGridOptions o;
  o.probHit = 0.4f;
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("GridGlobal/ProbHit"), std::string::npos);
  for (const char* bad : {"0", "-1"}) {
    try {
      GlobalGridOptions::fromParameters({{"Grid/CellSize", bad}});
      FAIL() << bad;
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find("Grid/CellSize"), std::string::npos) << e.what();
    }
    EXPECT_THROW(LocalGridOptions::fromParameters({{"Grid/CellSize", bad}}), ParameterError);
  }
  for (const char* bad : {"0", "-2"}) {
    try {
      GlobalGridOptions::fromParameters({{"GridGlobal/ReassemblyInterval", bad}}).validate();
      FAIL() << bad;
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find("GridGlobal/ReassemblyInterval"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(GlobalGridOptions::fromParameters({{"GridGlobal/ReassemblyInterval", "4"}}).reassemblyInterval, 4);
  const GlobalGridOptions fromDefaults = GlobalGridOptions::fromParameters({});
  EXPECT_TRUE(fromDefaults.IsValid());
  EXPECT_FLOAT_EQ(fromDefaults.probHit, 0.7f);
}

TEST(OccupancyGrid, LocalGridOptionsValidation) {
  LocalGridOptions o;
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o.cellSize = 0.0f;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("Grid/CellSize"), std::string::npos);
  EXPECT_THROW(createLocalGrid(SensorData(), o), ParameterError);
  o = LocalGridOptions();
  o.rangeMin = 2.0f;
  o.rangeMax = 1.0f;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("Grid/RangeMax"), std::string::npos);
  o = LocalGridOptions();
  o.normalsSegmentation = false;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("Grid/MaxGroundHeight"), std::string::npos);
  o.sensor = LocalGridOptions::Sensor::kScan;  // a 2D scan does not segment
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o = LocalGridOptions();
  o.stereo.numDisparities = 20;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("StereoBM/NumDisparities"), std::string::npos);
  const LocalGridOptions fromParams =
      LocalGridOptions::fromParameters({{"Grid/CellSize", "0.1"}, {"Grid/DepthRoiRatios", "0.1 0 0 0.2"}});
  EXPECT_FLOAT_EQ(fromParams.cellSize, 0.1f);
  EXPECT_FLOAT_EQ(fromParams.depthRoiRatios[3], 0.2f);
}

// Issue 10: nodes out of the Working Memory keep no cells in RAM; a re-assembly reads the cells
// of those it replays back through the loader, and the map is the one built with every node in
// RAM, whichever path runs.
TEST(OccupancyGrid, EvictedNodesAreReadBackByReassembliesAndTheMapIsUnchanged) {
  const ScanRun run = corridorRun(40);
  // The loop closure: the last ten nodes move 0.3 m, over the cells of the first ones.
  std::map<int, Transform> closed = run.poses;
  for (int id = 31; id <= 40; ++id) closed[id] = Transform(-0.3, 0.2, 0.05) * closed[id];
  const std::map<int, Transform> shiftedAll = shifted(closed, Transform(0.4, -0.2, 0.1));

  for (Path path : {Path::kRegion, Path::kFull}) {
    SCOPED_TRACE(pathName(path));
    GlobalGridOptions noCache = options();
    noCache.ltmCacheSize = 0.0f;  // every evicted node replayed is read back
    OccupancyGrid inRam(options()), evicting(noCache);
    std::vector<std::vector<int>> asked;
    evicting.setGridLoader([&](const std::vector<int>& ids) {
      asked.push_back(ids);
      std::map<int, LocalGrid> out;
      for (int id : ids) out[id] = run.grids.at(id);
      return out;
    });
    appendEvictingOld(run, inRam, evicting);  // a Working Memory of 10 nodes
    ASSERT_FALSE(::testing::Test::HasFailure());
    EXPECT_TRUE(asked.empty()) << "appending needs no evicted cells";
    EXPECT_EQ(evicting.cachedNodes(), 40u);
    EXPECT_EQ(evicting.residentNodes(), 10u);
    EXPECT_TRUE(evicting.hasLocalGrid(1));
    EXPECT_LT(evicting.memoryUsed(), inRam.memoryUsed());
    expectSameMap(inRam.map(), evicting.map());

    for (const auto& poses : {closed, shiftedAll}) {
      inRam.forceNextPath(path);
      evicting.forceNextPath(path);
      const GridUpdateSummary a = inRam.update(poses), b = evicting.update(poses);
      EXPECT_EQ(b.path, path);
      EXPECT_EQ(a.nodesReplayed, b.nodesReplayed);
      EXPECT_EQ(a.cellUpdates, b.cellUpdates);
      EXPECT_EQ(a.nodesLoaded, 0);
      EXPECT_GT(b.nodesLoaded, 0) << "the re-assembly replayed no evicted node: the test proves nothing";
      EXPECT_EQ(b.nodesNotLoaded, 0);
      expectSameMap(inRam.map(), evicting.map());
    }
    EXPECT_EQ(evicting.residentNodes(), 10u) << "cells read back are not kept";
    for (const std::vector<int>& ids : asked) EXPECT_LE(ids.size(), 64u);
  }
}

// What the map keeps of a node in the Long-Term Memory (its cells evicted): bounds, cell count,
// layer key and the tiles it was applied to (runs along rows), in about what one empty cell set
// would cost (it kept two of them before, and its tiles as a list of keys: 374 bytes here). The
// second lap drives over the first one's cells, so the storage's area stays the same and the
// difference is the 40 evicted nodes' bookkeeping.
TEST(OccupancyGrid, AnEvictedNodeKeepsOnlyItsBookkeeping) {
  const ScanRun run = corridorRun(40);
  GlobalGridOptions noCache = options();
  noCache.ltmCacheSize = 0.0f;
  OccupancyGrid grid(noCache);
  grid.setGridLoader([&](const std::vector<int>& ids) {
    std::map<int, LocalGrid> out;
    for (int id : ids) out[id] = run.grids.at((id - 1) % 40 + 1);
    return out;
  });
  std::map<int, Transform> poses;
  size_t oneLap = 0;
  for (int lap = 0; lap < 2; ++lap) {
    for (int i = 1; i <= 40; ++i) {
      ASSERT_TRUE(grid.addLocalGrid(lap * 40 + i, run.grids.at(i)));
      poses[lap * 40 + i] = run.poses.at(i);
    }
    grid.update(poses);
    for (int i = 1; i <= 40; ++i) ASSERT_TRUE(grid.evictLocalGrid(lap * 40 + i));
    if (lap == 0) oneLap = grid.memoryUsed();
  }
  EXPECT_EQ(grid.residentNodes(), 0u);
  // Beyond the pose it is assembled at (and that entry's map node), which every node keeps.
  const double perNode = double(grid.memoryUsed() - oneLap) / 40.0 - double(sizeof(Transform) + 64);
  EXPECT_GT(perNode, 0.0);
  EXPECT_LT(perNode, 128.0) << "bytes kept per evicted node (a cell set alone is over 100)";
}

// The same, with a loader that has lost the cells: the evicted nodes are left out (and counted),
// so a re-assembly that needed them gives another map. What the test above would see if an
// evicted node's cells were missing.
TEST(OccupancyGrid, EvictedNodesTheLoaderCannotGiveBackAreLeftOutAndCounted) {
  const ScanRun run = corridorRun(20);
  GlobalGridOptions noCache = options();
  noCache.ltmCacheSize = 0.0f;
  OccupancyGrid inRam(options()), lossy(noCache);
  EXPECT_FALSE(lossy.evictLocalGrid(1)) << "no loader: nothing to read the cells back from";
  lossy.setGridLoader(
      [&](const std::vector<int>& ids) {
        std::map<int, LocalGrid> out;
        for (int id : ids) {
          if (id % 2) out[id] = run.grids.at(id);  // even nodes lost
        }
        out[1] = run.grids.at(20);  // and node 1 comes back as another node's grid
        return out;
      });
  for (const auto& [id, g] : run.grids) {
    inRam.addLocalGrid(id, g);
    lossy.addLocalGrid(id, g);
  }
  inRam.update(run.poses);
  lossy.update(run.poses);
  for (int id = 1; id <= 10; ++id) ASSERT_TRUE(lossy.evictLocalGrid(id));
  EXPECT_FALSE(lossy.evictLocalGrid(99));
  const std::map<int, Transform> moved = shifted(run.poses, Transform(0.2, 0.1, 0.02));
  inRam.forceNextPath(Path::kFull);
  lossy.forceNextPath(Path::kFull);
  inRam.update(moved);
  const GridUpdateSummary s = lossy.update(moved);
  EXPECT_EQ(s.nodesLoaded, 4);     // 3 5 7 9
  EXPECT_EQ(s.nodesNotLoaded, 6);  // 1 (not its grid) 2 4 6 8 10
  const GridMap a = inRam.map(), b = lossy.map();
  EXPECT_TRUE(a.data.size() != b.data.size() || cv::countNonZero(a.data != b.data) > 0);
  // A node evicted and added again is in RAM again, counted once.
  lossy.addLocalGrid(2, run.grids.at(2));
  EXPECT_EQ(lossy.residentNodes(), 11u);
  lossy.removeLocalGrid(3);
  lossy.removeLocalGrid(12);
  EXPECT_EQ(lossy.residentNodes(), 10u);
  EXPECT_EQ(lossy.cachedNodes(), 18u);
}

// The cells of the evicted nodes used last stay in RAM within the budget: a second re-assembly
// over the same old nodes reads nothing back, and the map is still the same.
TEST(OccupancyGrid, RecentlyUsedEvictedCellsAreKeptWithinTheBudget) {
  const ScanRun run = corridorRun(30);
  int reads = 0;
  auto loader = [&](const std::vector<int>& ids) {
    reads += static_cast<int>(ids.size());
    std::map<int, LocalGrid> out;
    for (int id : ids) out[id] = run.grids.at(id);
    return out;
  };
  GlobalGridOptions smallCache = options(), largeCache = options();
  smallCache.ltmCacheSize = 60.0f / 1024.0f;  // 60 KB: a few nodes' cells
  largeCache.ltmCacheSize = 8.0f;             // all of them
  OccupancyGrid inRam(options()), small(smallCache), large(largeCache);
  small.setGridLoader(loader);
  large.setGridLoader(loader);
  for (OccupancyGrid* g : {&inRam, &small, &large}) {
    for (const auto& [id, grid] : run.grids) g->addLocalGrid(id, grid);
    g->update(run.poses);
  }
  for (int id = 1; id <= 25; ++id) {
    ASSERT_TRUE(small.evictLocalGrid(id));
    ASSERT_TRUE(large.evictLocalGrid(id));
  }
  const size_t smallBytes = small.memoryUsed(), largeBytes = large.memoryUsed();
  EXPECT_LT(smallBytes, largeBytes);
  EXPECT_LE(largeBytes, inRam.memoryUsed() + 25 * 512);  // evicted but kept: the same cells
  for (int k = 1; k <= 3; ++k) {
    const std::map<int, Transform> moved = shifted(run.poses, Transform(0.1 * k, 0.05, 0.02 * k));
    for (OccupancyGrid* g : {&inRam, &small, &large}) g->forceNextPath(Path::kFull);
    inRam.update(moved);
    const GridUpdateSummary s = small.update(moved), l = large.update(moved);
    EXPECT_EQ(l.nodesLoaded, 0);
    EXPECT_GE(s.nodesLoaded, 10);  // the budget holds some 14 of the 25
    EXPECT_EQ(s.nodesNotLoaded + l.nodesNotLoaded, 0);
    expectSameMap(inRam.map(), small.map());
    expectSameMap(inRam.map(), large.map());
  }
  EXPECT_LE(small.memoryUsed(), smallBytes + 4096) << "the budget holds";
}

namespace {

// Every cell's probability, compared to the bit over the first map's extent.
void expectSameCells(const OccupancyGrid& a, const OccupancyGrid& b) {
  const GridMap m = a.map();
  ASSERT_FALSE(m.empty());
  int differing = 0;
  for (int r = 0; r < m.height(); ++r) {
    for (int c = 0; c < m.width(); ++c) {
      const double x = m.originX + (c + 0.5) * m.resolution, y = m.originY + (r + 0.5) * m.resolution;
      differing += a.probability(x, y) != b.probability(x, y);
    }
  }
  EXPECT_EQ(differing, 0);
}

// Fraction of the cells of `a` with the same class (-1 / 0 / 100) in `b`.
double sameClassShare(const GridMap& a, const GridMap& b) {
  if (a.empty() || a.data.size() != b.data.size()) return 0.0;
  return 1.0 - double(cv::countNonZero(a.data != b.data)) / double(a.data.total());
}

}  // namespace

// Issue 10: a tile's Long-Term Memory layer holds the cells of its evicted nodes, so that a
// re-assembly replays (and reads back) only the nodes not in it. Below the clamping bounds cell
// updates commute, so the map is then the one built with every node in RAM to the bit: the
// bookkeeping (which node is in which layer, which tiles start from their layer) is checked
// exactly. The robot's Working Memory is its last 10 nodes; the loop closure moves them again and
// again; a retrieved node (25) moves with them once, then leaves for the LTM again.
TEST(OccupancyGrid, LongTermMemoryLayersSpareReadingOldNodesBackAndKeepTheMap) {
  const ScanRun run = corridorRun(40);
  for (const bool clamped : {false, true}) {
    for (Path path : {Path::kRegion, Path::kFull}) {
      SCOPED_TRACE(std::string(pathName(path)) + (clamped ? ", clamped" : ", below the clamping bounds"));
      GlobalGridOptions o = options();
      if (!clamped) {
        o.probHit = 0.52f;  // 0.08 a hit: a cell seen by all 40 nodes stays far from +-6.9
        o.probMiss = 0.48f;
        o.probClampingMin = 0.001f;
        o.probClampingMax = 0.999f;
      }
      GlobalGridOptions noCache = o;
      noCache.ltmCacheSize = 0.0f;
      OccupancyGrid inRam(o), layered(noCache);
      int reads = 0;
      layered.setGridLoader([&](const std::vector<int>& ids) {
        reads += static_cast<int>(ids.size());
        std::map<int, LocalGrid> out;
        for (int id : ids) out[id] = run.grids.at(id == 41 ? 20 : id);
        return out;
      });
      std::map<int, Transform> graph = appendEvictingOld(run, inRam, layered);  // a WM of 10 nodes
      ASSERT_FALSE(::testing::Test::HasFailure());
      auto closeLoop = [&](double dx, std::initializer_list<int> alsoMoved) {
        for (int id = 31; id <= 40; ++id) graph[id] = Transform(dx, 0.1, 0.03) * run.poses.at(id);
        for (int id : alsoMoved) graph[id] = Transform(0.0, dx, 0.0) * run.poses.at(id);
        inRam.forceNextPath(path);
        layered.forceNextPath(path);
        inRam.update(graph);
        const GridUpdateSummary s = layered.update(graph);
        EXPECT_EQ(s.path, path);
        EXPECT_EQ(s.nodesNotLoaded, 0);
        if (clamped) {
          // Above the bounds the order of updates matters: a layer's nodes come before the others.
          EXPECT_GT(sameClassShare(inRam.map(), layered.map()), 0.99);
        } else {
          expectSameCells(inRam, layered);
        }
        return s;
      };
      // The first re-assembly reads the old nodes in its tiles back and keeps them in layers.
      const GridUpdateSummary first = closeLoop(-0.3, {});
      EXPECT_GT(first.nodesLoaded, 5);
      // The next ones over the same area read nothing back but a node new to the map that was
      // evicted before it was assembled (a map loaded from its database): it is in no layer yet.
      ASSERT_TRUE(inRam.addLocalGrid(41, run.grids.at(20)));
      ASSERT_TRUE(layered.addLocalGrid(41, run.grids.at(20)));
      ASSERT_TRUE(layered.evictLocalGrid(41));
      graph[41] = Transform(0.05, 0.05, 0.02) * run.poses.at(20);
      const GridUpdateSummary second = closeLoop(-0.2, {});
      EXPECT_EQ(second.nodesLoaded, 1);
      EXPECT_GE(second.nodesInLayers, 15);  // the old nodes the first one read back (18 / 30)
      if (path == Path::kFull) {
        EXPECT_EQ(second.nodesReplayed + second.nodesInLayers, 41);
      }
      EXPECT_EQ(closeLoop(-0.23, {}).nodesLoaded, 1) << "41 joins the layers of its tiles";
      EXPECT_EQ(closeLoop(-0.2, {}).nodesLoaded, 0);
      // A retrieved node optimised with the Working Memory leaves its layers: their old nodes are
      // read back once ...
      const GridUpdateSummary retrieved = closeLoop(-0.25, {25});
      EXPECT_GT(retrieved.nodesLoaded, 1);
      // Then only 25 itself, replayed while it moves (the region path reads it for its tiles and
      // for its cells: no cache here).
      EXPECT_LE(closeLoop(-0.22, {25}).nodesLoaded, 2);
      // ... and when it is back in the LTM it joins them at the next re-assembly.
      EXPECT_TRUE(layered.evictLocalGrid(25));
      closeLoop(-0.21, {});
      EXPECT_EQ(closeLoop(-0.2, {}).nodesLoaded, 0);
      // Replaced and removed nodes leave their layers too.
      ASSERT_TRUE(inRam.addLocalGrid(12, run.grids.at(13)));
      ASSERT_TRUE(layered.addLocalGrid(12, run.grids.at(13)));
      graph.erase(3);
      EXPECT_GT(closeLoop(-0.3, {}).nodesLoaded, 0);
      EXPECT_GT(reads, 0);
      EXPECT_LT(layered.memoryUsed(), inRam.memoryUsed());
    }
  }
}

namespace {

// A grid of `run`'s nodes given at `poses` (ids absent from it are left out), assembled at once.
GridMap freshMap(const ScanRun& run, const std::map<int, Transform>& poses) {
  OccupancyGrid fresh(options());
  for (const auto& [id, pose] : poses) fresh.addLocalGrid(id, run.grids.at(id));
  fresh.update(poses);
  return fresh.map();
}

}  // namespace

// GridGlobal/ReassemblyInterval: graph changes wait, and add up, for N - 1 updates while new
// nodes are appended; the N-th update gives exactly the map of the last graph.
TEST(OccupancyGrid, DeferredReassemblyAddsChangesUpAndEndsOnTheMapOfTheLastGraph) {
  const ScanRun run = corridorRun(30);
  GlobalGridOptions o = options();
  o.reassemblyInterval = 3;
  OccupancyGrid grid(o);
  std::map<int, Transform> graph;
  for (int id = 1; id <= 20; ++id) {
    ASSERT_TRUE(grid.addLocalGrid(id, run.grids.at(id)));
    graph[id] = run.poses.at(id);
    EXPECT_EQ(grid.update(graph).updatesDeferred, 0);  // appending never waits
  }
  const std::map<int, Transform> before = graph;
  // A loop closure moves nodes 15-20; node 21 comes.
  grid.addLocalGrid(21, run.grids.at(21));
  graph[21] = run.poses.at(21);
  for (int id = 15; id <= 20; ++id) graph[id] = Transform(0, 0.3, 0) * run.poses.at(id);
  GridUpdateSummary s = grid.update(graph);
  EXPECT_EQ(s.updatesDeferred, 1) << s.why;
  EXPECT_EQ(grid.pendingUpdates(), 1);
  EXPECT_EQ(s.path, Path::kIncremental);
  EXPECT_EQ(s.nodesAdded, 1);
  EXPECT_EQ(s.nodesReplayed, 0);
  std::map<int, Transform> shown = before;  // the moved nodes where they were, 21 on top
  shown[21] = graph[21];
  expectSameMap(freshMap(run, shown), grid.map());
  for (int id = 15; id <= 20; ++id) EXPECT_TRUE(grid.assembledPoses().at(id) == before.at(id)) << id;

  // The next correction moves them further and drops node 3; node 22 comes.
  grid.addLocalGrid(22, run.grids.at(22));
  graph[22] = run.poses.at(22);
  for (int id = 15; id <= 20; ++id) graph[id] = Transform(0, 0.5, 0.05) * run.poses.at(id);
  graph.erase(3);
  s = grid.update(graph);
  EXPECT_EQ(s.updatesDeferred, 2) << s.why;
  EXPECT_EQ(s.nodesAdded, 1);

  // The third update re-assembles both corrections together.
  grid.addLocalGrid(23, run.grids.at(23));
  graph[23] = run.poses.at(23);
  s = grid.update(graph);
  EXPECT_EQ(s.updatesDeferred, 0) << s.why;
  EXPECT_EQ(grid.pendingUpdates(), 0);
  EXPECT_EQ(s.nodesMoved, 6);
  EXPECT_EQ(s.nodesRemoved, 1);
  EXPECT_NE(s.path, Path::kIncremental);
  expectSameMap(freshMap(run, graph), grid.map());
  EXPECT_EQ(grid.assembledPoses().size(), graph.size());
}

TEST(OccupancyGrid, DeferredChangesUndoneOrWithoutANewNodeLeaveNothingWaiting) {
  const ScanRun run = corridorRun(16);
  GlobalGridOptions o = options();
  o.reassemblyInterval = 5;
  OccupancyGrid grid(o);
  std::map<int, Transform> graph;
  for (int id = 1; id <= 16; ++id) grid.addLocalGrid(id, run.grids.at(id));
  for (int id = 1; id <= 10; ++id) graph[id] = run.poses.at(id);
  grid.update(graph);
  auto withNode = [&](std::map<int, Transform> g, int id) {
    graph[id] = g[id] = run.poses.at(id);
    return g;
  };
  const Transform shift(0.2, 0, 0);
  std::map<int, Transform> moved = withNode(graph, 11);
  moved[4] = shift * graph[4];
  EXPECT_EQ(grid.update(moved).updatesDeferred, 1);
  // Optimisation puts node 4 back: nothing differs from the map any more.
  GridUpdateSummary s = grid.update(withNode(graph, 12));
  EXPECT_EQ(s.updatesDeferred, 0) << s.why;
  EXPECT_EQ(s.path, Path::kIncremental);
  EXPECT_EQ(grid.pendingUpdates(), 0);
  expectSameMap(freshMap(run, graph), grid.map());
  // An update without a new node (the robot stands, a link added by hand) re-assembles at once.
  moved = withNode(graph, 13);
  moved[4] = shift * graph[4];
  EXPECT_EQ(grid.update(moved).updatesDeferred, 1);
  s = grid.update(moved);
  EXPECT_EQ(s.updatesDeferred, 0);
  EXPECT_EQ(s.nodesMoved, 1);
  EXPECT_EQ(grid.pendingUpdates(), 0);
  expectSameMap(freshMap(run, moved), grid.map());
  // MaxNodes selects anew with every node: no deferral with it.
  o.maxNodes = 8;
  OccupancyGrid newest(o);
  for (const auto& [id, g] : run.grids) newest.addLocalGrid(id, g);
  newest.update(graph);
  moved = withNode(graph, 14);
  moved[12] = shift * graph[12];
  s = newest.update(moved);
  EXPECT_EQ(s.updatesDeferred, 0);
  EXPECT_EQ(s.nodesMoved, 1);
}

// A node whose grid was removed (the map_assembler invalidating a node whose data changed) and
// that moved in the same update leaves the map; finding it moved must not need its cells.
TEST(OccupancyGrid, ANodeRemovedAndMovedInOneUpdateLeavesTheMap) {
  const ScanRun run = corridorRun(6);
  OccupancyGrid grid(options());
  for (const auto& [id, g] : run.grids) grid.addLocalGrid(id, g);
  grid.update(run.poses);
  grid.removeLocalGrid(3);
  std::map<int, Transform> moved = run.poses;
  moved[3] = Transform(0.5, 0, 0) * moved[3];
  GridUpdateSummary s;
  ASSERT_NO_THROW(s = grid.update(moved));
  EXPECT_EQ(s.nodesRemoved, 1);
  std::map<int, Transform> without = run.poses;
  without.erase(3);
  expectSameMap(freshMap(run, without), grid.map());
}

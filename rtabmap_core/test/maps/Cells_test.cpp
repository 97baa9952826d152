// The compact cells the global grid caches for every node of the map (src/maps/Cells.h): the
// same cells, bit for bit, in a few bytes per cell, so the map's memory per node stays small.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>
#include <tuple>

#include "../../src/maps/Cells.h"
#include "../../src/maps/GridStorage.h"
#include "maps/MapsTestUtil.h"
#include "rtabmap_core/maps/Cloud.h"
#include "rtabmap_core/maps/LocalGridStages.h"
#include "rtabmap_core/maps/OccupancyGrid.h"

using namespace rtabmap;
using maps_detail::CellSet;

namespace {

using Bits = std::tuple<uint32_t, uint32_t, uint32_t>;
Bits bits(float x, float y, float z) {
  uint32_t a, b, c;
  std::memcpy(&a, &x, 4);
  std::memcpy(&b, &y, 4);
  std::memcpy(&c, &z, 4);
  return {a, b, c};
}

std::set<Bits> decoded(const CellSet& set, size_t* calls = nullptr) {
  std::set<Bits> out;
  set.forEachBatch([&](const float* x, const float* y, const float* z, int n) {
    EXPECT_GT(n, 0);
    EXPECT_LE(n, maps_detail::kChunk);
    for (int k = 0; k < n; ++k) out.insert(bits(x[k], y[k], z[k]));
    if (calls) ++*calls;
  });
  return out;
}

std::set<Bits> asBits(const std::vector<cv::Point3f>& points) {
  std::set<Bits> out;
  for (const cv::Point3f& p : points) out.insert(bits(p.x, p.y, p.z));
  return out;
}

// A 30 m laser (the simulator's UTM-30LX: 1081 beams over 270 degrees) in a 12 m x 7 m room
// with pillars: thousands of ray-traced free cells, as in the soak (7,800 a node on average).
LocalGrid hallScan(const Transform& pose) {
  test::World2D world = test::World2D::room(0, 0, 12, 7);
  for (int i = 0; i < 3; ++i) world.boxes.push_back({{2.5 + 3.5 * i, 3.2, -1}, {2.9 + 3.5 * i, 3.6, 1}});
  LocalGridOptions o;
  o.cellSize = 0.05f;
  o.rangeMax = 0.0f;
  return rayTraceScan2D(test::simulateScan(world, pose, 1081, 1.5 * M_PI, 30.0), o);
}

}  // namespace

TEST(Cells, RayTracedFreeSpaceBecomesRunsThatDecodeToTheSameFloats) {
  const LocalGrid g = hallScan(Transform(6.0, 4.0, 0.3));
  const std::vector<cv::Point3f> free = cloudFromCells(g.empty).points;
  ASSERT_GT(free.size(), 10000u);
  const CellSet set(free, g.cellSize);
  EXPECT_TRUE(set.runLength());
  EXPECT_EQ(set.count(), free.size());  // ray tracing gives each cell once
  size_t calls = 0;
  EXPECT_EQ(decoded(set, &calls), asBits(free));
  EXPECT_EQ(calls, (free.size() + maps_detail::kChunk - 1) / maps_detail::kChunk);
  // Floats would take 12 bytes a cell; runs well under one.
  EXPECT_LT(double(set.bytes()) / double(free.size()), 0.5);
}

TEST(Cells, CellsOffTheLatticeKeepTheirFloats) {
  const LocalGrid g = hallScan(Transform(6.0, 4.0, 0.3));
  const std::vector<cv::Point3f> obstacles = cloudFromCells(g.obstacles).points;  // means of hits
  ASSERT_GT(obstacles.size(), 100u);
  const CellSet set(obstacles, g.cellSize);
  EXPECT_FALSE(set.runLength());
  EXPECT_EQ(decoded(set), asBits(obstacles));
  EXPECT_EQ(set.bytes(), obstacles.size() * 2 * sizeof(float));  // z = 0: not stored

  // One cell off the lattice, or one above the plane, keeps the whole set as floats, z included.
  std::vector<cv::Point3f> centres = {{0.025f, 0.025f, 0.f}, {0.075f, 0.025f, 0.f}, {0.125f, 0.025f, 0.f}};
  std::vector<cv::Point3f> raised = centres;
  raised[1].z = 0.3f;
  const CellSet r(raised, 0.05f);
  EXPECT_FALSE(r.runLength());
  EXPECT_EQ(decoded(r), asBits(raised));
  std::vector<cv::Point3f> off = centres;
  off[2].x = 0.126f;
  EXPECT_EQ(decoded(CellSet(off, 0.05f)), asBits(off));
  EXPECT_TRUE(CellSet(centres, 0.05f).empty() == false);
}

TEST(Cells, NegativeCellsAndDuplicatesAndEmptySets) {
  std::vector<cv::Point3f> cells;
  for (int r = -40; r < 40; ++r) {
    for (int c = -60; c < 20; ++c) cells.emplace_back((c + 0.5f) * 0.05f, (r + 0.5f) * 0.05f, 0.f);
  }
  const std::vector<cv::Point3f> unique = cells;
  cells.insert(cells.end(), unique.begin(), unique.begin() + 100);  // given twice
  const CellSet set(cells, 0.05f);
  EXPECT_TRUE(set.runLength());
  EXPECT_EQ(set.count(), unique.size());
  EXPECT_EQ(decoded(set), asBits(unique));
  EXPECT_EQ(set.bytes(), 80u * 6u);  // one run per row

  const CellSet none({}, 0.05f);
  EXPECT_TRUE(none.empty());
  EXPECT_EQ(none.bytes(), 0u);
  EXPECT_TRUE(decoded(none).empty());
}

// What the map holds per node is what grows with a long run (the soak: thousands of nodes, all
// kept by the global grid): a few KB for a 30 m scan, not the 12 bytes a cell of float x y z.
TEST(Cells, TheGlobalGridCachesAScanNodeInAFewKilobytes) {
  GlobalGridOptions o;
  OccupancyGrid grid(o);
  std::map<int, Transform> poses;
  size_t cells = 0;
  for (int i = 0; i < 20; ++i) {
    const Transform pose(1.0 + 0.5 * i, 2.0 + 0.3 * std::sin(i), 0.2 * i);
    const LocalGrid g = hallScan(pose);
    cells += size_t(g.obstacles.total() + g.empty.total());
    ASSERT_TRUE(grid.addLocalGrid(i + 1, g));
    poses[i + 1] = pose;
  }
  const size_t before = grid.memoryUsed();  // the cache only: nothing assembled yet
  // Over 10,000 cells a node here (120 KB as float x y z); obstacles (hit means) stay floats.
  EXPECT_GT(cells / 20, 10000u);
  EXPECT_LT(double(before) / 20.0, 16 * 1024.0);
  EXPECT_LT(double(before) / double(cells), 1.0);
  grid.update(poses);
  EXPECT_EQ(grid.assembledPoses().size(), 20u);
}

// The world tiles the global grid keeps for every node (maps_detail::TileSet): runs along a row
// give back exactly the keys they were made of, in the same order, across the signs of the tile
// coordinates (the key's column is unsigned: -1 sorts after 0 and does not extend its run).
TEST(Cells, TileRunsGiveBackTheSameTileKeys) {
  using maps_detail::tileKeyOfTile;
  std::vector<int64_t> keys;
  for (int row : {-3, -1, 0, 2}) {
    for (int col = -4; col <= 3; ++col) {
      if (col == 1 && row == 0) continue;  // a gap: two runs in that row
      keys.push_back(tileKeyOfTile(col, row));
    }
  }
  keys.push_back(tileKeyOfTile(40, 7));  // a lone tile
  std::sort(keys.begin(), keys.end());
  const maps_detail::TileSet set(keys);
  EXPECT_EQ(set.keys(), keys);
  // Per row: the non-negative columns, then the negative ones; row 0 has one more for its gap.
  EXPECT_EQ(set.runs(), 4u * 2u + 1u + 1u);
  EXPECT_LT(set.bytes(), keys.size() * sizeof(int64_t) / 2);
  for (int64_t k : keys) {
    const int col = maps_detail::tileCol(k) * maps_detail::kTile, row = maps_detail::tileRow(k) * maps_detail::kTile;
    EXPECT_EQ(maps_detail::tileKey(col, row), k) << "the key of the tile's first cell";
  }

  int asked = 0;
  EXPECT_TRUE(set.any([&](int64_t k) { ++asked; return k == keys[5]; }));
  EXPECT_EQ(asked, 6) << "any() stops at the first tile it accepts";
  EXPECT_FALSE(set.any([](int64_t k) { return k == maps_detail::tileKeyOfTile(1, 0); }));
  EXPECT_TRUE(maps_detail::TileSet().keys().empty());
  EXPECT_TRUE(maps_detail::TileSet(std::vector<int64_t>{}).keys().empty());
}

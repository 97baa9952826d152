#include "rtabmap_slam_node/MapsAssembler.h"

#include <gtest/gtest.h>

#include "TestGrids.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap_slam_node {
namespace {

using rtabmap::Transform;

using test::wallAhead;

// A source that counts what it is asked, with a grid per node id.
struct CountingSource {
  std::map<int, rtabmap::LocalGrid> grids;
  std::map<int, int> asked;
  MapsAssembler::GridSource fn() {
    return [this](int id) -> std::optional<rtabmap::LocalGrid> {
      ++asked[id];
      auto it = grids.find(id);
      if (it == grids.end()) return std::nullopt;
      return it->second;
    };
  }
  int total() const {
    int n = 0;
    for (const auto& [id, k] : asked) n += k;
    return n;
  }
};

bool cloudHasPointNear(const rtabmap::Cloud& c, float x, float y, float z, float tolerance) {
  for (const cv::Point3f& p : c.points) {
    if (std::abs(p.x - x) <= tolerance && std::abs(p.y - y) <= tolerance && std::abs(p.z - z) <= tolerance) return true;
  }
  return false;
}

MapsWanted want(bool cloud, bool octomap, bool grid) {
  MapsWanted w;
  w.cloud = cloud;
  w.octomap = octomap;
  w.grid = grid;
  return w;
}

TEST(MapsAssembler, NothingWantedCostsNothing) {
  CountingSource source;
  source.grids = {{1, wallAhead()}, {2, wallAhead()}};
  MapsAssembler maps;
  const std::map<int, Transform> poses = {{1, Transform::Identity()}, {2, Transform(1, 0, 0, 0, 0, 0)}};
  for (int i = 0; i < 3; ++i) {
    const MapsUpdateSummary s = maps.update(poses, MapsWanted(), source.fn());
    EXPECT_EQ(s.gridsFetched, 0);
    EXPECT_EQ(s.cloudNodes + s.octomapNodes + s.gridNodes, 0);
  }
  EXPECT_EQ(source.total(), 0) << "the source was asked although nobody listens";
  EXPECT_EQ(maps.cloudMap(), nullptr);
  EXPECT_EQ(maps.octoMap(), nullptr);
  EXPECT_EQ(maps.occupancyGrid(), nullptr);
  EXPECT_EQ(maps.assemblingUpdates(), 0);
}

TEST(MapsAssembler, FirstWantedBuildsFromTheWholeGraphThenOnlyFetchesNewNodes) {
  CountingSource source;
  for (int id = 1; id <= 4; ++id) source.grids[id] = wallAhead();
  MapsAssembler maps;
  std::map<int, Transform> poses = {{1, Transform::Identity()}, {2, Transform(2, 0, 0, 0, 0, 0)},
                                    {3, Transform(4, 0, 0, 0, 0, 0)}};
  maps.update(poses, MapsWanted(), source.fn());  // nobody yet
  MapsUpdateSummary s = maps.update(poses, want(true, false, false), source.fn());
  EXPECT_EQ(s.gridsFetched, 3);
  EXPECT_EQ(s.cloudNodes, 3);
  ASSERT_NE(maps.cloudMap(), nullptr);
  // Node 3's wall, in the map frame: 4 + 1.025 m.
  EXPECT_TRUE(cloudHasPointNear(maps.cloudMap()->cloud(), 5.025f, 0.025f, 0.025f, 0.03f));

  EXPECT_TRUE(s.cloudChanged);
  EXPECT_FALSE(s.octomapChanged || s.gridChanged) << "not wanted";
  s = maps.update(poses, want(true, false, false), source.fn());
  EXPECT_EQ(s.gridsFetched, 0) << "grids already assembled were asked again";
  EXPECT_FALSE(s.cloudChanged) << "same graph: the published cloud is still right";
  poses[4] = Transform(6, 0, 0, 0, 0, 0);
  s = maps.update(poses, want(true, false, false), source.fn());
  EXPECT_EQ(s.gridsFetched, 1);
  EXPECT_EQ(s.cloudNodes, 4);
  EXPECT_TRUE(s.cloudChanged);
  for (int id = 1; id <= 4; ++id) EXPECT_EQ(source.asked[id], 1) << "node " << id;
  EXPECT_EQ(maps.assemblingUpdates(), 3);
}

TEST(MapsAssembler, MovedNodesMoveInTheCloudAndTheOctoMap) {
  CountingSource source;
  source.grids = {{1, wallAhead()}, {2, wallAhead()}};
  MapsAssembler maps;
  std::map<int, Transform> poses = {{1, Transform::Identity()}, {2, Transform(3, 0, 0, 0, 0, 0)}};
  maps.update(poses, want(true, true, false), source.fn());
  ASSERT_NE(maps.octoMap(), nullptr);
  const Eigen::Vector3f oldWall(4.025f, 0.125f, 0.125f), newWall(4.025f, 2.125f, 0.125f);
  EXPECT_EQ(maps.octoMap()->state(oldWall), rtabmap::VoxelState::kObstacle);
  EXPECT_NE(maps.octoMap()->state(newWall), rtabmap::VoxelState::kObstacle);

  // Optimisation moves node 2 by 2 m along y: its wall follows, the old place empties.
  poses[2] = Transform(3, 2, 0, 0, 0, 0);
  MapsUpdateSummary s = maps.update(poses, want(true, true, false), source.fn());
  EXPECT_EQ(s.gridsFetched, 0);
  EXPECT_TRUE(s.octomapRebuilt);
  EXPECT_TRUE(s.octomapChanged && s.cloudChanged);
  EXPECT_EQ(maps.octoMap()->state(newWall), rtabmap::VoxelState::kObstacle);
  EXPECT_NE(maps.octoMap()->state(oldWall), rtabmap::VoxelState::kObstacle);
  EXPECT_TRUE(cloudHasPointNear(maps.cloudMap()->cloud(), 4.025f, 2.025f, 0.025f, 0.03f));
  EXPECT_FALSE(cloudHasPointNear(maps.cloudMap()->cloud(), 4.025f, 0.025f, 0.025f, 0.03f));
  // Ground under node 1 stays ground (free in the octomap's 2D projection).
  EXPECT_EQ(maps.octoMap()->state(Eigen::Vector3f(0.525f, 0.125f, 0.0f)), rtabmap::VoxelState::kGround);
  // Moved by less than GridGlobal/UpdateError (1 cm, cells included): nothing to redo.
  poses[2] = Transform(3.002, 2, 0, 0, 0, 0);
  s = maps.update(poses, want(true, true, false), source.fn());
  EXPECT_FALSE(s.octomapRebuilt);
  EXPECT_FALSE(s.octomapChanged || s.cloudChanged);
}

TEST(MapsAssembler, OccupancyGridHasTheWallAndTheFloor) {
  CountingSource source;
  source.grids = {{1, wallAhead()}};
  MapsAssembler maps;
  const Transform yawLeft(1, 1, 0, 0, 0, M_PI / 2);  // the wall ahead is at y = 2
  EXPECT_TRUE(maps.update({{1, yawLeft}}, want(false, false, true), source.fn()).gridChanged);
  ASSERT_NE(maps.occupancyGrid(), nullptr);
  const rtabmap::GridMap map = maps.occupancyGrid()->map();
  ASSERT_FALSE(map.empty());
  EXPECT_EQ(map.at(0.875, 2.025), rtabmap::GridMap::kOccupied);  // (1 - 0.125, 1 + 1.025)
  EXPECT_EQ(map.at(0.875, 1.5), rtabmap::GridMap::kFree);
  EXPECT_EQ(map.at(1.5, 1.5), rtabmap::GridMap::kUnknown);
}

TEST(MapsAssembler, NoLongerWantedIsDroppedAndRebuiltFromEverythingWhenWantedAgain) {
  CountingSource source;
  source.grids = {{1, wallAhead()}, {2, wallAhead()}};
  MapsAssembler maps;
  std::map<int, Transform> poses = {{1, Transform::Identity()}};
  maps.update(poses, want(true, true, false), source.fn());
  EXPECT_EQ(source.asked[1], 1) << "one fetch serves both maps";
  maps.update(poses, want(false, true, false), source.fn());
  EXPECT_EQ(maps.cloudMap(), nullptr);
  ASSERT_NE(maps.octoMap(), nullptr);
  poses[2] = Transform(2, 0, 0, 0, 0, 0);
  maps.update(poses, MapsWanted(), source.fn());
  EXPECT_EQ(maps.octoMap(), nullptr);
  EXPECT_EQ(source.asked[2], 0) << "node 2 came while nobody listened";
  const MapsUpdateSummary s = maps.update(poses, want(true, false, false), source.fn());
  EXPECT_EQ(s.gridsFetched, 2);
  EXPECT_EQ(s.cloudNodes, 2);
  EXPECT_TRUE(cloudHasPointNear(maps.cloudMap()->cloud(), 3.025f, 0.025f, 0.025f, 0.03f));
}

TEST(MapsAssembler, NodesWithoutGridAreAskedOnceAndInvalidateAsksAgain) {
  CountingSource source;
  source.grids = {{1, wallAhead()}};
  MapsAssembler maps;
  const std::map<int, Transform> poses = {{1, Transform::Identity()}, {2, Transform(2, 0, 0, 0, 0, 0)}};
  for (int i = 0; i < 3; ++i) maps.update(poses, want(true, false, false), source.fn());
  EXPECT_EQ(source.asked[2], 1);
  EXPECT_EQ(maps.cloudMap()->cloud().size(), wallAhead().obstacles.cols + wallAhead().ground.cols);

  // Node 2 now has a grid (e.g. its id was reused after a reset) and node 1 another one.
  source.grids[2] = wallAhead();
  rtabmap::LocalGrid shifted = wallAhead();
  shifted.obstacles = rtabmap::cellsFromCloud(rtabmap::transformCloud(rtabmap::cloudFromCells(shifted.obstacles),
                                                                      Transform(0, 0, 1, 0, 0, 0)), false);
  source.grids[1] = shifted;
  maps.invalidate(1);
  maps.invalidate(2);
  const MapsUpdateSummary s = maps.update(poses, want(true, false, false), source.fn());
  EXPECT_EQ(s.gridsFetched, 2);
  EXPECT_EQ(s.cloudNodes, 2);
  EXPECT_TRUE(cloudHasPointNear(maps.cloudMap()->cloud(), 1.025f, 0.025f, 1.025f, 0.03f)) << "node 1's new grid";
  EXPECT_FALSE(cloudHasPointNear(maps.cloudMap()->cloud(), 1.025f, 0.025f, 0.025f, 0.03f)) << "node 1's old grid";
  EXPECT_TRUE(cloudHasPointNear(maps.cloudMap()->cloud(), 3.025f, 0.025f, 0.025f, 0.03f)) << "node 2's grid";
}

TEST(MapsAssembler, AGridAMapRefusesIsSaidOnceAndTheOtherMapsStillUseIt) {
  CountingSource source;
  source.grids = {{1, wallAhead(0.1f)}};  // the maps' cell size is 0.05
  MapsAssembler maps;
  const std::map<int, Transform> poses = {{1, Transform::Identity()}};
  MapsUpdateSummary s = maps.update(poses, want(true, false, true), source.fn());
  ASSERT_EQ(s.refused.size(), 1u);
  EXPECT_NE(s.refused[0].find("occupancy grid"), std::string::npos) << s.refused[0];
  EXPECT_EQ(s.cloudNodes, 1);
  EXPECT_EQ(s.gridNodes, 0);
  s = maps.update(poses, want(true, false, true), source.fn());
  EXPECT_TRUE(s.refused.empty());
  EXPECT_EQ(s.gridsFetched, 0);
}

TEST(MapsAssembler, InvalidParametersAreRefusedAtConstruction) {
  EXPECT_THROW(MapsAssembler(rtabmap::ParametersMap{{"GridGlobal/ProbHit", "0.3"}}), rtabmap::ParameterError);
  MapsAssembler maps(rtabmap::ParametersMap{{"GridGlobal/OctoMapTreeDepth", "14"}});
  EXPECT_EQ(maps.octomapTreeDepth(), 14);
}

TEST(LocalGridStore, KeepsEachNodesGridAndSaysWhenItChanged) {
  LocalGridStore store;
  EXPECT_TRUE(store.add(1, wallAhead()));
  EXPECT_FALSE(store.add(1, wallAhead())) << "the same grid again (publish_map) is nothing new";
  EXPECT_FALSE(store.add(2, rtabmap::LocalGrid())) << "a node without grid (graph view)";
  EXPECT_FALSE(store.get(2).has_value());
  ASSERT_TRUE(store.get(1).has_value());
  EXPECT_TRUE(sameLocalGrid(*store.get(1), wallAhead()));

  rtabmap::LocalGrid other = wallAhead();
  other.obstacles = other.obstacles.clone();
  other.obstacles.at<cv::Vec3f>(0, 3)[2] += 0.05f;  // one cell one level up
  EXPECT_FALSE(sameLocalGrid(other, wallAhead()));
  EXPECT_TRUE(store.add(1, other)) << "another grid under the same id (the SLAM node was reset)";
  EXPECT_TRUE(sameLocalGrid(*store.get(1), other));
  rtabmap::LocalGrid moved = other;
  moved.viewPoint.z() = 0.5f;
  EXPECT_TRUE(store.add(1, moved));
  EXPECT_EQ(store.size(), 1u);
}

TEST(LocalGridStore, FeedsTheAssemblerThroughItsSource) {
  LocalGridStore store;
  store.add(1, wallAhead());
  MapsAssembler maps;
  const MapsUpdateSummary s = maps.update({{1, Transform::Identity()}, {2, Transform(2, 0, 0, 0, 0, 0)}},
                                          want(true, false, false), [&store](int id) { return store.get(id); });
  EXPECT_EQ(s.gridsFetched, 2);
  EXPECT_EQ(s.cloudNodes, 1);
  // Node 2's data comes later (e.g. publish_map): the store says it is new, the maps take it.
  ASSERT_TRUE(store.add(2, wallAhead()));
  maps.invalidate(2);
  const MapsUpdateSummary t = maps.update({{1, Transform::Identity()}, {2, Transform(2, 0, 0, 0, 0, 0)}},
                                          want(true, false, false), [&store](int id) { return store.get(id); });
  EXPECT_EQ(t.gridsFetched, 1);
  EXPECT_EQ(t.cloudNodes, 2);
}

}  // namespace
}  // namespace rtabmap_slam_node

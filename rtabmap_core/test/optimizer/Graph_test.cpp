// graph:: utilities against hand-computed answers.
#include <gtest/gtest.h>

#include <cmath>

#include "rtabmap_core/optimizer/Graph.h"

namespace rtabmap {
namespace {

using graph::Links;
using graph::Poses;

Links chain(std::initializer_list<std::pair<int, int>> pairs, Link::Type type = Link::kNeighbor) {
  Links links;
  for (const auto& [a, b] : pairs) links.emplace(a, Link(a, b, type, Transform(1, 0, 0)));
  return links;
}

TEST(Graph, FilterLinksByType) {
  Links links = chain({{1, 2}, {2, 3}});
  links.emplace(3, Link(3, 1, Link::kGlobalClosure, Transform(0, 0, 0)));
  links.emplace(3, Link(3, 3, Link::kPosePrior, Transform(0, 0, 0)));
  EXPECT_EQ(graph::filterLinks(links, Link::kNeighbor).size(), 2u);          // removed
  EXPECT_EQ(graph::filterLinks(links, Link::kNeighbor, true).size(), 2u);    // kept only
  const Links loops = graph::filterLinks(links, Link::kGlobalClosure, true);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops.begin()->second.from(), 3);
  EXPECT_EQ(graph::filterLinks(links, {Link::kNeighbor, Link::kPosePrior}).size(), 1u);
  EXPECT_TRUE(graph::isLoopClosureOrProximity(Link::kLocalSpaceClosure));
  EXPECT_TRUE(graph::isLoopClosureOrProximity(Link::kUserClosure));
  EXPECT_FALSE(graph::isLoopClosureOrProximity(Link::kNeighbor));
  EXPECT_FALSE(graph::isLoopClosureOrProximity(Link::kVirtualClosure));
  EXPECT_FALSE(graph::isLoopClosureOrProximity(Link::kLandmark));
}

TEST(Graph, DuplicateLinksInBothDirectionsAreKeptOnce) {
  const Link forward(1, 2, Link::kNeighbor, Transform(1, 0.5, 0.2));
  Links links;
  links.emplace(1, forward);
  links.emplace(2, forward.inverse());                                            // duplicate
  links.emplace(2, Link(2, 1, Link::kGlobalClosure, forward.transform().inverse()));  // other type
  links.emplace(2, Link(2, 1, Link::kNeighbor, Transform(-1, 0, 0)));              // other value
  const Links filtered = graph::filterDuplicateLinks(links);
  EXPECT_EQ(filtered.size(), 3u);
  EXPECT_EQ(filtered.begin()->second.from(), 1);
}

TEST(Graph, FindLink) {
  Links links = chain({{1, 2}, {2, 3}});
  links.emplace(3, Link(3, 1, Link::kGlobalClosure, Transform(0, 0, 0)));
  auto it = graph::findLink(links, 2, 1);
  ASSERT_NE(it, links.end());
  EXPECT_EQ(it->second.from(), 1);
  EXPECT_EQ(graph::findLink(links, 2, 1, false), links.end());
  EXPECT_EQ(graph::findLink(links, 1, 3, true, Link::kNeighbor), links.end());
  it = graph::findLink(links, 1, 3, true, Link::kGlobalClosure);
  ASSERT_NE(it, links.end());
  EXPECT_EQ(it->second.from(), 3);
}

TEST(Graph, ConnectedComponents) {
  Links links = chain({{1, 2}, {2, 3}, {10, 11}});
  links.emplace(5, Link(5, 5, Link::kPosePrior, Transform(0, 0, 0)));  // connects nothing
  EXPECT_EQ(graph::connectedComponent(3, links), (std::set<int>{1, 2, 3}));
  EXPECT_EQ(graph::connectedComponent(5, links), (std::set<int>{5}));
  const std::set<int> allowed{1, 3};
  EXPECT_EQ(graph::connectedComponent(1, links, &allowed), (std::set<int>{1}));

  // Two branches listed apart and joined last (through a landmark, id < 0), a cycle, and the
  // other component beside them: every node of the root's component, none of the other's.
  Links joined = chain({{20, 21}, {30, 31}, {21, 22}, {31, 32}, {22, 20}});
  joined.emplace(32, Link(32, -1, Link::kLandmark, Transform(0, 0, 0)));
  joined.emplace(22, Link(22, -1, Link::kLandmark, Transform(0, 0, 0)));
  joined.emplace(40, Link(40, 41, Link::kNeighbor, Transform(0, 0, 0)));
  EXPECT_EQ(graph::connectedComponent(30, joined), (std::set<int>{-1, 20, 21, 22, 30, 31, 32}));
  EXPECT_EQ(graph::connectedComponent(41, joined), (std::set<int>{40, 41}));
  EXPECT_EQ(graph::connectedComponent(99, joined), (std::set<int>{99}));  // in no link: itself

  Poses poses;
  for (int id : {1, 2, 3, 5, 10, 11}) poses.emplace(id, Transform(0, 0, 0));
  const auto components = graph::connectedComponents(poses, links);
  ASSERT_EQ(components.size(), 3u);
  EXPECT_EQ(components[0], (std::set<int>{1, 2, 3}));
  EXPECT_EQ(components[1], (std::set<int>{10, 11}));  // largest first
  EXPECT_EQ(components[2], (std::set<int>{5}));
  // Ties keep the smallest first id first.
  poses.emplace(12, Transform(0, 0, 0));
  poses.emplace(13, Transform(0, 0, 0));
  links.emplace(12, Link(12, 13, Link::kNeighbor, Transform(1, 0, 0)));
  const auto tied = graph::connectedComponents(poses, links);
  ASSERT_EQ(tied.size(), 4u);
  EXPECT_EQ(tied[1], (std::set<int>{10, 11}));
  EXPECT_EQ(tied[2], (std::set<int>{12, 13}));
}

TEST(Graph, LocalMapStopsAtNodesOutsideTheSet) {
  // 1-2-3-4-5 and 3-5; the set lacks 4: from 1 the local map is 1, 2, 3, 5 (through 3-5).
  Links links = chain({{1, 2}, {2, 3}, {3, 4}, {4, 5}, {6, 7}});
  links.emplace(3, Link(3, 5, Link::kLocalSpaceClosure, Transform(2, 0, 0)));
  Poses poses;
  for (int id : {1, 2, 3, 5, 6, 7}) poses.emplace(id, Transform(id, 0, 0));
  const graph::Subgraph local = graph::localMap(1, poses, links);
  std::set<int> ids;
  for (const auto& [id, pose] : local.poses) ids.insert(id);
  EXPECT_EQ(ids, (std::set<int>{1, 2, 3, 5}));
  EXPECT_EQ(local.links.size(), 3u);  // 1-2, 2-3, 3-5
  EXPECT_TRUE(graph::localMap(4, poses, links).poses.empty());
}

TEST(Graph, NearestNodesAndRadius) {
  Poses poses;
  for (int i = 0; i < 10; ++i) poses.emplace(i + 1, Transform(i, 0, 0));  // id i+1 at x = i
  poses[5] = Transform(4, 0, 0, 0, 0, M_PI);                               // x = 4, turned back
  poses.emplace(20, Transform(3.4, 0, 10, 0, 0, 0));                       // 10 m above
  const Transform target(3.4, 0, 0, 0, 0, 0);
  const auto nearest = graph::findNearestNodes(poses, target, 3);
  ASSERT_EQ(nearest.size(), 3u);
  EXPECT_EQ(nearest[0].first, 4);  // x = 3, 0.4 m
  EXPECT_NEAR(nearest[0].second, 0.4, 1e-12);
  EXPECT_EQ(nearest[1].first, 5);  // x = 4, 0.6 m
  EXPECT_EQ(nearest[2].first, 3);  // x = 2, 1.4 m
  // In 2D the node above is on the target.
  double distance = -1;
  EXPECT_EQ(graph::findNearestNode(poses, target, &distance, true), 20);
  EXPECT_NEAR(distance, 0.0, 1e-12);
  EXPECT_EQ(graph::findNearestNode(Poses(), target), 0);

  const auto inRadius = graph::findNodesInRadius(poses, target, 1.0);
  EXPECT_EQ(inRadius.size(), 2u);
  EXPECT_NEAR(inRadius.at(4), 0.4, 1e-12);
  EXPECT_NEAR(inRadius.at(5), 0.6, 1e-12);
  // Orientation filter: node 5 faces the other way.
  const auto facing = graph::findNodesInRadius(poses, target, 1.0, false, 0.5);
  EXPECT_EQ(facing.size(), 1u);
  EXPECT_TRUE(facing.count(4));
  EXPECT_EQ(graph::findNodesInRadius(poses, target, 1.0, true).size(), 3u);  // + node 20
}

// 1 (0,0, yaw 0), 2 (2,0, yaw 0), 3 (2,2, yaw pi/2), 4 (0,1.9, yaw pi); links 1-2, 2-3, 1-4, 4-3.
struct Square {
  Poses poses{{1, Transform(0, 0, 0)},
              {2, Transform(2, 0, 0)},
              {3, Transform(2, 2, M_PI / 2)},
              {4, Transform(0, 1.9, M_PI)},
              {9, Transform(5, 5, 0)}};
  Links links = chain({{1, 2}, {2, 3}, {1, 4}, {4, 3}});
};

std::vector<int> idsOf(const graph::Path& path) {
  std::vector<int> ids;
  for (const auto& [id, pose] : path.nodes) ids.push_back(id);
  return ids;
}

TEST(Graph, DijkstraWithDistance) {
  const Square s;
  const graph::Path path = graph::computePath(s.poses, s.links, 1, 3);
  ASSERT_TRUE(path.found);
  // Via 4: 1.9 + sqrt(4 + 0.01) = 3.9025 < 4 via 2.
  EXPECT_EQ(idsOf(path), (std::vector<int>{1, 4, 3}));
  EXPECT_NEAR(path.cost, 1.9 + std::sqrt(4.01), 1e-12);
  EXPECT_NEAR(path.nodes[1].second.y(), 1.9, 1e-12);
  // Links are undirected.
  EXPECT_EQ(idsOf(graph::computePath(s.poses, s.links, 3, 1)), (std::vector<int>{3, 4, 1}));
  // Unreachable, absent, and the trivial path.
  EXPECT_FALSE(graph::computePath(s.poses, s.links, 1, 9).found);
  EXPECT_FALSE(graph::computePath(s.poses, s.links, 1, 42).found);
  const graph::Path self = graph::computePath(s.poses, s.links, 2, 2);
  EXPECT_TRUE(self.found);
  EXPECT_EQ(idsOf(self), (std::vector<int>{2}));
  EXPECT_EQ(self.cost, 0.0);
}

TEST(Graph, DijkstraWithTheAngularCostOfTheSplamPaper) {
  const Square s;
  graph::PathCost cost;
  cost.linearVelocity = 0.5;
  cost.angularVelocity = 1.0;
  cost.is2D = true;
  // Via 2: 4 m / 0.5 + turns 0 + pi/2 = 8 + pi/2 = 9.5708.
  // Via 4: 3.9025 / 0.5 + turns pi + pi/2 = 7.805 + 4.712 = 12.517.
  const graph::Path path = graph::computePath(s.poses, s.links, 1, 3, cost);
  ASSERT_TRUE(path.found);
  EXPECT_EQ(idsOf(path), (std::vector<int>{1, 2, 3}));
  EXPECT_NEAR(path.cost, 8.0 + M_PI / 2, 1e-12);
  EXPECT_NEAR(graph::linkCost(s.poses.at(1), s.poses.at(4), cost), 1.9 / 0.5 + M_PI, 1e-12);
  // Angular velocity only: distance in metres plus turning time.
  graph::PathCost turnsOnly;
  turnsOnly.angularVelocity = 2.0;
  EXPECT_NEAR(graph::linkCost(s.poses.at(2), s.poses.at(3), turnsOnly), 2.0 + M_PI / 4, 1e-12);
}

}  // namespace
}  // namespace rtabmap

#include "rtabmap_slam_node/MapViews.h"

#include <gtest/gtest.h>

namespace rtabmap_slam_node {
namespace {

using rtabmap::Link;
using rtabmap::Transform;

std_msgs::Header mapHeader() {
  std_msgs::Header h;
  h.frame_id = "map";
  return h;
}

const visualization_msgs::Marker* find(const visualization_msgs::MarkerArray& a, const std::string& ns) {
  for (const auto& m : a.markers) {
    if (m.ns == ns && m.action == visualization_msgs::Marker::ADD) return &m;
  }
  return nullptr;
}

TEST(MapViews, PathFollowsTheOptimisedPosesOfItsNodes) {
  const NodePath planned = {{3, Transform(1, 0, 0, 0, 0, 0)}, {4, Transform(2, 0, 0, 0, 0, 0)}};
  const NodePath path = refreshPath(planned, {{4, Transform(2, 0.5, 0, 0, 0, M_PI / 2)}, {9, Transform::Identity()}});
  ASSERT_EQ(path.size(), 2u);
  EXPECT_DOUBLE_EQ(path[0].second.x(), 1.0) << "not in the map's poses: as planned";
  EXPECT_DOUBLE_EQ(path[1].second.y(), 0.5);
  const nav_msgs::Path msg = pathToMsg(path, mapHeader());
  ASSERT_EQ(msg.poses.size(), 2u);
  EXPECT_EQ(msg.header.frame_id, "map");
  EXPECT_EQ(msg.poses[1].header.frame_id, "map");
  EXPECT_DOUBLE_EQ(msg.poses[1].pose.position.y, 0.5);
  EXPECT_NEAR(msg.poses[1].pose.orientation.z, std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(msg.poses[1].pose.orientation.w, std::sqrt(0.5), 1e-9);
}

TEST(MapViews, LabelsAreTextAtTheirNodesAfterADeleteAll) {
  const std::map<int, Transform> poses = {{1, Transform(1, 2, 0, 0, 0, 0)}, {2, Transform(3, 4, 0, 0, 0, 0)}};
  const auto a = labelMarkers({{1, "kitchen"}, {2, ""}, {7, "elsewhere"}}, poses, mapHeader());
  ASSERT_EQ(a.markers.size(), 2u) << "an empty label and a node without a pose are not drawn";
  EXPECT_EQ(a.markers[0].action, visualization_msgs::Marker::DELETEALL);
  const visualization_msgs::Marker& m = a.markers[1];
  EXPECT_EQ(m.type, visualization_msgs::Marker::TEXT_VIEW_FACING);
  EXPECT_EQ(m.text, "kitchen");
  EXPECT_EQ(m.id, 1);
  EXPECT_DOUBLE_EQ(m.pose.position.x, 1.0);
  EXPECT_DOUBLE_EQ(m.pose.position.y, 2.0);
  EXPECT_GT(m.scale.z, 0.0);
  EXPECT_GT(m.color.a, 0.0f);
}

TEST(MapViews, GraphLinksAreDrawnOneListPerKind) {
  const std::map<int, Transform> poses = {
      {1, Transform(0, 0, 0, 0, 0, 0)}, {2, Transform(1, 0, 0, 0, 0, 0)}, {3, Transform(2, 0, 0, 0, 0, 0)}};
  std::multimap<int, Link> links;
  links.emplace(1, Link(1, 2, Link::kNeighbor, Transform(1, 0, 0, 0, 0, 0)));
  links.emplace(2, Link(2, 3, Link::kNeighbor, Transform(1, 0, 0, 0, 0, 0)));
  links.emplace(3, Link(3, 1, Link::kGlobalClosure, Transform(-2, 0, 0, 0, 0, 0)));
  links.emplace(3, Link(3, 9, Link::kLocalSpaceClosure, Transform::Identity()));  // 9 has no pose
  links.emplace(1, Link(1, 1, Link::kPosePrior, Transform::Identity()));
  links.emplace(2, Link(2, -4, Link::kLandmark, Transform(0.5, 1, 0, 0, 0, 0)));
  std::map<int, Transform> withLandmark = poses;
  withLandmark.emplace(-4, Transform(1.5, 1, 0, 0, 0, 0));
  const auto a = graphMarkers(withLandmark, links, mapHeader());
  EXPECT_EQ(a.markers.front().action, visualization_msgs::Marker::DELETEALL);
  const auto* nodes = find(a, "nodes");
  ASSERT_NE(nodes, nullptr);
  EXPECT_EQ(nodes->type, visualization_msgs::Marker::SPHERE_LIST);
  EXPECT_EQ(nodes->points.size(), 3u);
  const auto* neighbours = find(a, "neighbor");
  ASSERT_NE(neighbours, nullptr);
  EXPECT_EQ(neighbours->type, visualization_msgs::Marker::LINE_LIST);
  EXPECT_EQ(neighbours->points.size(), 4u) << "two links, two ends each";
  const auto* loops = find(a, "loop_closure");
  ASSERT_NE(loops, nullptr);
  ASSERT_EQ(loops->points.size(), 2u);
  EXPECT_DOUBLE_EQ(loops->points[0].x, 2.0);
  EXPECT_DOUBLE_EQ(loops->points[1].x, 0.0);
  EXPECT_NE(loops->color.r, neighbours->color.r) << "kinds have their own colour";
  EXPECT_EQ(find(a, "proximity"), nullptr) << "a link to a node without a pose is not drawn";
  const auto* landmarks = find(a, "landmarks");
  ASSERT_NE(landmarks, nullptr);
  EXPECT_EQ(landmarks->type, visualization_msgs::Marker::CUBE_LIST);
  ASSERT_EQ(landmarks->points.size(), 1u) << "the landmark, not among the nodes";
  EXPECT_DOUBLE_EQ(landmarks->points[0].x, 1.5);
  const auto* seen = find(a, "landmark");
  ASSERT_NE(seen, nullptr);
  EXPECT_EQ(seen->points.size(), 2u);
  EXPECT_EQ(graphMarkerNamespace(Link::kPosePrior), "");
  EXPECT_EQ(graphMarkerNamespace(Link::kLocalTimeClosure), "proximity");
}

TEST(MapViews, NodesInRadiusNearestFirstAndKNearest) {
  const std::map<int, Transform> poses = {{1, Transform(0, 0, 0, 0, 0, 0)},
                                          {2, Transform(1, 0, 0, 0, 0, 0)},
                                          {3, Transform(0, 0, 2.5, 0, 0, 0)},
                                          {4, Transform(0.4, 0.3, 0, 0, 0, 0)}};
  const Transform center(0.1, 0, 0, 0, 0, 0);
  NodePath r = nodesInRadius(poses, center, 1.0, 0);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0].first, 1);
  EXPECT_EQ(r[1].first, 4);
  EXPECT_EQ(r[2].first, 2);
  r = nodesInRadius(poses, center, 1.0, 2);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[1].first, 4);
  EXPECT_EQ(nodesInRadius(poses, center, 0.0, 0).size(), 4u) << "radius 0: any distance (3D: node 3 is 2.5 m up)";
  EXPECT_EQ(nodesInRadius(poses, center, 2.0, 0).size(), 3u);
}

}  // namespace
}  // namespace rtabmap_slam_node

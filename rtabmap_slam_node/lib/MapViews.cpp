#include "rtabmap_slam_node/MapViews.h"

#include <algorithm>

namespace rtabmap_slam_node {
namespace {

geometry_msgs::Pose poseMsg(const rtabmap::Transform& t) {
  geometry_msgs::Pose p;
  p.position.x = t.x();
  p.position.y = t.y();
  p.position.z = t.z();
  const Eigen::Quaterniond q = t.quaternion();
  p.orientation.x = q.x();
  p.orientation.y = q.y();
  p.orientation.z = q.z();
  p.orientation.w = q.w();
  return p;
}

geometry_msgs::Point pointMsg(const rtabmap::Transform& t) {
  geometry_msgs::Point p;
  p.x = t.x();
  p.y = t.y();
  p.z = t.z();
  return p;
}

std_msgs::ColorRGBA colour(float r, float g, float b) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = 1.0f;
  return c;
}

visualization_msgs::Marker deleteAll(const std_msgs::Header& header) {
  visualization_msgs::Marker m;
  m.header = header;
  m.action = visualization_msgs::Marker::DELETEALL;
  return m;
}

visualization_msgs::Marker marker(const std_msgs::Header& header, const std::string& ns, int id, int type) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  return m;
}

}  // namespace

NodePath refreshPath(const NodePath& path, const std::map<int, rtabmap::Transform>& poses) {
  NodePath out = path;
  for (auto& [id, pose] : out) {
    auto it = poses.find(id);
    if (it != poses.end() && !it->second.isNull()) pose = it->second;
  }
  return out;
}

nav_msgs::Path pathToMsg(const NodePath& path, const std_msgs::Header& header) {
  nav_msgs::Path msg;
  msg.header = header;
  for (const auto& [id, pose] : path) {
    geometry_msgs::PoseStamped p;
    p.header = header;
    p.pose = poseMsg(pose);
    msg.poses.push_back(p);
  }
  return msg;
}

visualization_msgs::MarkerArray labelMarkers(const std::map<int, std::string>& labels,
                                             const std::map<int, rtabmap::Transform>& poses,
                                             const std_msgs::Header& header) {
  visualization_msgs::MarkerArray out;
  out.markers.push_back(deleteAll(header));
  for (const auto& [id, label] : labels) {
    auto it = poses.find(id);
    if (label.empty() || it == poses.end() || it->second.isNull()) continue;
    visualization_msgs::Marker m = marker(header, "labels", id, visualization_msgs::Marker::TEXT_VIEW_FACING);
    m.pose.position = pointMsg(it->second);
    m.pose.position.z += 0.3;  // above the graph's node spheres
    m.scale.z = 0.3;           // text height (m)
    m.color = colour(1.0f, 1.0f, 1.0f);
    m.text = label;
    out.markers.push_back(m);
  }
  return out;
}

std::string graphMarkerNamespace(rtabmap::Link::Type type) {
  switch (type) {
    case rtabmap::Link::kNeighbor:
    case rtabmap::Link::kNeighborMerged:
      return "neighbor";
    case rtabmap::Link::kGlobalClosure:
      return "loop_closure";
    case rtabmap::Link::kLocalSpaceClosure:
    case rtabmap::Link::kLocalTimeClosure:
      return "proximity";
    case rtabmap::Link::kUserClosure:
    case rtabmap::Link::kVirtualClosure:
    case rtabmap::Link::kTemporary:
      return "user";
    case rtabmap::Link::kLandmark:
      return "landmark";
    default:
      return "";
  }
}

visualization_msgs::MarkerArray graphMarkers(const std::map<int, rtabmap::Transform>& poses,
                                             const std::multimap<int, rtabmap::Link>& links,
                                             const std_msgs::Header& header) {
  visualization_msgs::MarkerArray out;
  out.markers.push_back(deleteAll(header));
  if (poses.empty()) return out;
  visualization_msgs::Marker nodes = marker(header, "nodes", 0, visualization_msgs::Marker::SPHERE_LIST);
  nodes.scale.x = nodes.scale.y = nodes.scale.z = 0.05;
  nodes.color = colour(0.0f, 1.0f, 0.0f);
  visualization_msgs::Marker landmarks = marker(header, "landmarks", 0, visualization_msgs::Marker::CUBE_LIST);
  landmarks.scale.x = landmarks.scale.y = landmarks.scale.z = 0.1;
  landmarks.color = colour(1.0f, 0.5f, 0.0f);
  for (const auto& [id, pose] : poses) (id < 0 ? landmarks : nodes).points.push_back(pointMsg(pose));
  if (!nodes.points.empty()) out.markers.push_back(nodes);
  if (!landmarks.points.empty()) out.markers.push_back(landmarks);

  const std::vector<std::pair<std::string, std_msgs::ColorRGBA>> kinds = {
      {"neighbor", colour(0.0f, 0.0f, 1.0f)},
      {"loop_closure", colour(1.0f, 0.0f, 0.0f)},
      {"proximity", colour(1.0f, 1.0f, 0.0f)},
      {"user", colour(0.0f, 1.0f, 1.0f)},
      {"landmark", colour(1.0f, 0.0f, 1.0f)}};
  for (size_t k = 0; k < kinds.size(); ++k) {
    visualization_msgs::Marker lines = marker(header, kinds[k].first, 0, visualization_msgs::Marker::LINE_LIST);
    lines.scale.x = 0.02;  // line width (m)
    lines.color = kinds[k].second;
    for (const auto& [from, link] : links) {
      auto a = poses.find(link.from());
      auto b = poses.find(link.to());
      if (a == poses.end() || b == poses.end() || graphMarkerNamespace(link.type()) != kinds[k].first) continue;
      lines.points.push_back(pointMsg(a->second));
      lines.points.push_back(pointMsg(b->second));
    }
    if (!lines.points.empty()) out.markers.push_back(lines);
  }
  return out;
}

NodePath nodesInRadius(const std::map<int, rtabmap::Transform>& poses, const rtabmap::Transform& center,
                       double radius, int k) {
  std::vector<std::pair<double, int>> byDistance;
  for (const auto& [id, pose] : poses) {
    if (pose.isNull()) continue;
    const double d = pose.getDistance(center);
    if (radius <= 0.0 || d <= radius) byDistance.emplace_back(d, id);
  }
  std::sort(byDistance.begin(), byDistance.end());
  if (k > 0 && byDistance.size() > static_cast<size_t>(k)) byDistance.resize(k);
  NodePath out;
  for (const auto& [d, id] : byDistance) out.emplace_back(id, poses.at(id));
  return out;
}

}  // namespace rtabmap_slam_node

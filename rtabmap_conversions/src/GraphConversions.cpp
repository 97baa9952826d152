#include "rtabmap_conversions/GraphConversions.h"

#include "Support.h"
#include "rtabmap_conversions/OdometryConversions.h"
#include "rtabmap_conversions/TransformConversions.h"

namespace rtabmap_conversions {

rtabmap_ros::Link linkToMsg(const rtabmap::Link& link) {
  rtabmap_ros::Link msg;
  msg.fromId = link.from();
  msg.toId = link.to();
  msg.type = static_cast<int32_t>(link.type());
  msg.transform = transformToMsg(link.transform());
  msg.information = covarianceToMsg(link.infMatrix());
  return msg;
}

std::optional<rtabmap::Link> linkFromMsg(const rtabmap_ros::Link& msg, std::string* error) {
  const std::string what = "link " + std::to_string(msg.fromId) + " -> " + std::to_string(msg.toId);
  const rtabmap::Link::Type type = rtabmap::Link::typeFromInt(msg.type);
  if (type == rtabmap::Link::kUndef) {
    return detail::fail(error, what + " has unknown type " + std::to_string(msg.type) + " (expected 0.." +
                                   std::to_string(rtabmap::Link::kTypeCount - 1) + ")");
  }
  const rtabmap::Transform transform = transformFromMsg(msg.transform);
  if (transform.isNull()) {
    return detail::fail(error, what + " (" + rtabmap::Link::typeName(type) +
                                   ") has a null or NaN transform (zero quaternion or non-finite values)");
  }
  if (!detail::allFinite(msg.information)) {
    return detail::fail(error, what + " (" + rtabmap::Link::typeName(type) + ") has a NaN or infinite information matrix");
  }
  return rtabmap::Link(msg.fromId, msg.toId, type, transform, covarianceFromMsg(msg.information));
}

rtabmap_ros::MapGraph mapGraphToMsg(const std::map<int, rtabmap::Transform>& poses,
                                    const std::multimap<int, rtabmap::Link>& links,
                                    const rtabmap::Transform& mapToOdom, const std_msgs::Header& header) {
  rtabmap_ros::MapGraph msg;
  msg.header = header;
  msg.mapToOdom = transformToMsg(mapToOdom);
  msg.posesId.reserve(poses.size());
  msg.poses.reserve(poses.size());
  for (const auto& [id, pose] : poses) {
    msg.posesId.push_back(id);
    msg.poses.push_back(transformToPoseMsg(pose));
  }
  msg.links.reserve(links.size());
  for (const auto& entry : links) msg.links.push_back(linkToMsg(entry.second));
  return msg;
}

std::optional<MapGraph> mapGraphFromMsg(const rtabmap_ros::MapGraph& msg, std::string* error) {
  if (msg.posesId.size() != msg.poses.size()) {
    return detail::fail(error, "MapGraph has " + std::to_string(msg.posesId.size()) + " pose ids for " +
                                   std::to_string(msg.poses.size()) + " poses");
  }
  MapGraph graph;
  graph.mapToOdom = transformFromMsg(msg.mapToOdom);
  for (size_t i = 0; i < msg.poses.size(); ++i) {
    const rtabmap::Transform pose = transformFromPoseMsg(msg.poses[i]);
    if (pose.isNull()) {
      return detail::fail(error, "MapGraph pose of node " + std::to_string(msg.posesId[i]) + " is null or NaN");
    }
    graph.poses[msg.posesId[i]] = pose;
  }
  for (const rtabmap_ros::Link& l : msg.links) {
    std::string why;
    std::optional<rtabmap::Link> link = linkFromMsg(l, &why);
    if (!link) return detail::fail(error, "MapGraph: " + why);
    graph.links.emplace(link->from(), *link);
  }
  return graph;
}

}  // namespace rtabmap_conversions

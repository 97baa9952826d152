#pragma once
// The pose graph in messages: rtabmap::Link <-> rtabmap_ros/Link, and poses + links +
// map -> odom correction <-> rtabmap_ros/MapGraph (published on `mapGraph`).
//
// A Link message keeps the type numbers of the core (never renumbered), the transform from
// `fromId` to `toId` in fromId's frame and the 6x6 information matrix row-major. A link's user
// data has no field in the message and is not carried.
#include <rtabmap_ros/Link.h>
#include <rtabmap_ros/MapGraph.h>
#include <std_msgs/Header.h>

#include <map>
#include <optional>
#include <string>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap_conversions {

rtabmap_ros::Link linkToMsg(const rtabmap::Link& link);
// Errors: an unknown type number, a null / NaN transform, a NaN information matrix.
std::optional<rtabmap::Link> linkFromMsg(const rtabmap_ros::Link& msg, std::string* error = nullptr);

struct MapGraph {
  std::map<int, rtabmap::Transform> poses;  // node id -> optimised pose in the map frame
  std::multimap<int, rtabmap::Link> links;  // keyed by link.from()
  rtabmap::Transform mapToOdom;             // null if unknown
};

rtabmap_ros::MapGraph mapGraphToMsg(const std::map<int, rtabmap::Transform>& poses,
                                    const std::multimap<int, rtabmap::Link>& links,
                                    const rtabmap::Transform& mapToOdom, const std_msgs::Header& header);
// Errors: posesId and poses of different lengths, a null / NaN pose, an invalid link (which
// one, and why).
std::optional<MapGraph> mapGraphFromMsg(const rtabmap_ros::MapGraph& msg, std::string* error = nullptr);

}  // namespace rtabmap_conversions

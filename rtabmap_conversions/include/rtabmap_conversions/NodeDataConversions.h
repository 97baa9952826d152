#pragma once
// Nodes of the map in messages: rtabmap::Signature <-> rtabmap_ros/NodeData, and the whole map
// (graph + nodes) <-> rtabmap_ros/MapData (published on `mapData`, read by map_assembler).
//
// NodeData carries a node's compressed sensor data as the database stores it (image, depth or
// right image, scan, user data: the SensorData's compressed bytes, passed through; raw-only
// data is compressed first), its rectified camera intrinsics (fx fy cx cy width height and
// local transform per camera; for stereo, each camera's left intrinsics plus the message's one
// baseline; float32 in the message), the scan's format, max points, max range and local transform, the local occupancy
// grid (zlib blobs of the cell matrices), its visual words, and GPS.
// What the message has no field for is not carried: the scan's minimum range and beam
// geometry, camera distortion (nodes hold rectified images anyway), velocity, links (MapData
// carries them in its graph; mapDataFromMsg puts them back on their nodes), and a baseline per
// stereo camera: the classic message has one `baseline` field, so several stereo cameras come
// back with the first camera's baseline (nodeDataToMsg logs a warning when they differ).
#include <rtabmap_ros/MapData.h>
#include <rtabmap_ros/NodeData.h>
#include <std_msgs/Header.h>

#include <map>
#include <optional>
#include <string>

#include "rtabmap_conversions/GraphConversions.h"
#include "rtabmap_core/memory/Signature.h"

namespace rtabmap_conversions {

// withSensorData = false leaves out the images, scan, user data and grid (the graph view of a
// node: pose, words, calibration), as `mapData` publishes nodes it already sent.
rtabmap_ros::NodeData nodeDataToMsg(const rtabmap::Signature& node, bool withSensorData = true);
// Errors: camera arrays of different lengths, an unknown scan format, corrupt grid or
// descriptor blobs, word arrays that do not match.
std::optional<rtabmap::Signature> nodeDataFromMsg(const rtabmap_ros::NodeData& msg, std::string* error = nullptr);

struct MapData {
  MapGraph graph;
  std::map<int, rtabmap::Signature> nodes;  // with the graph's links from each node added
};

rtabmap_ros::MapData mapDataToMsg(const std::map<int, rtabmap::Transform>& poses,
                                  const std::multimap<int, rtabmap::Link>& links,
                                  const std::map<int, rtabmap::Signature>& nodes,
                                  const rtabmap::Transform& mapToOdom, const std_msgs::Header& header,
                                  bool withSensorData = true);
std::optional<MapData> mapDataFromMsg(const rtabmap_ros::MapData& msg, std::string* error = nullptr);

}  // namespace rtabmap_conversions

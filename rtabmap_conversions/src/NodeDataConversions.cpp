#include "rtabmap_conversions/NodeDataConversions.h"

#include <ros/console.h>

#include <cmath>

#include "Support.h"
#include "rtabmap_conversions/FeatureConversions.h"
#include "rtabmap_conversions/TransformConversions.h"
#include "rtabmap_core/codec/Compression.h"

namespace rtabmap_conversions {

namespace {

std::vector<uint8_t> blobOf(const cv::Mat& m) {
  return m.empty() ? std::vector<uint8_t>() : rtabmap::codec::compressData(m);
}

bool matOfBlob(const std::vector<uint8_t>& bytes, const char* name, cv::Mat& out, std::string* error) {
  if (bytes.empty()) {
    out = cv::Mat();
    return true;
  }
  try {
    out = rtabmap::codec::uncompressData(bytes);
    return true;
  } catch (const std::exception& e) {
    detail::fail(error, std::string("corrupt ") + name + ": " + e.what());
    return false;
  }
}

void addCamera(rtabmap_ros::NodeData& msg, const rtabmap::CameraModel& model) {
  msg.fx.push_back(static_cast<float>(model.fx()));
  msg.fy.push_back(static_cast<float>(model.fy()));
  msg.cx.push_back(static_cast<float>(model.cx()));
  msg.cy.push_back(static_cast<float>(model.cy()));
  msg.width.push_back(static_cast<float>(model.imageWidth()));
  msg.height.push_back(static_cast<float>(model.imageHeight()));
  msg.localTransform.push_back(transformToMsg(model.localTransform()));
}

// Fills the camera models of `data` from the message arrays (stereo when a baseline is set).
bool setCameras(const rtabmap_ros::NodeData& msg, rtabmap::SensorData& data, std::string* error) {
  const size_t n = msg.fx.size();
  if (msg.fy.size() != n || msg.cx.size() != n || msg.cy.size() != n || msg.width.size() != n ||
      msg.height.size() != n || msg.localTransform.size() != n) {
    detail::fail(error, "camera arrays of different lengths (fx " + std::to_string(n) + ", fy " +
                            std::to_string(msg.fy.size()) + ", cx " + std::to_string(msg.cx.size()) + ", cy " +
                            std::to_string(msg.cy.size()) + ", width " + std::to_string(msg.width.size()) +
                            ", height " + std::to_string(msg.height.size()) + ", localTransform " +
                            std::to_string(msg.localTransform.size()) + ")");
    return false;
  }
  std::vector<rtabmap::CameraModel> models;
  std::vector<rtabmap::StereoCameraModel> stereo;
  for (size_t i = 0; i < n; ++i) {
    const cv::Size size(static_cast<int>(msg.width[i]), static_cast<int>(msg.height[i]));
    const rtabmap::Transform local = transformFromMsg(msg.localTransform[i]);
    // A baseline makes every camera of the node stereo (the classic message's convention).
    if (msg.baseline > 0.0f) {
      stereo.emplace_back(msg.fx[i], msg.fy[i], msg.cx[i], msg.cy[i], msg.baseline, local, size);
    } else {
      models.emplace_back(msg.fx[i], msg.fy[i], msg.cx[i], msg.cy[i], local, 0.0, size);
    }
  }
  if (!stereo.empty()) {
    data.setStereoImage(cv::Mat(), cv::Mat(), stereo);
  } else {
    data.setRGBDImage(cv::Mat(), cv::Mat(), models);
  }
  return true;
}

// The message has one baseline for all stereo cameras: say so when the node's cameras differ,
// since their depths will be off by the ratio of the baselines for whoever reads the message.
void warnIfBaselinesDiffer(const std::vector<rtabmap::StereoCameraModel>& stereo, int id) {
  for (const rtabmap::StereoCameraModel& model : stereo) {
    if (std::abs(model.baseline() - stereo.front().baseline()) > 1e-6) {
      ROS_WARN_THROTTLE(10.0, "NodeData of node %d: its %zu stereo cameras have different baselines (%g and %g m) "
                        "but the message carries one: the first camera's is sent for all",
                        id, stereo.size(), stereo.front().baseline(), model.baseline());
      return;
    }
  }
}

}  // namespace

rtabmap_ros::NodeData nodeDataToMsg(const rtabmap::Signature& node, bool withSensorData) {
  rtabmap_ros::NodeData msg;
  msg.id = node.id();
  msg.mapId = node.mapId();
  msg.weight = node.weight();
  msg.stamp = node.stamp();
  msg.label = node.label();
  msg.pose = transformToPoseMsg(node.getPose());
  msg.groundTruthPose = transformToPoseMsg(node.getGroundTruthPose());

  const rtabmap::SensorData& data = node.sensorData();
  const rtabmap::GPS& gps = data.gps();
  msg.gps.stamp = gps.stamp;
  msg.gps.longitude = gps.longitude;
  msg.gps.latitude = gps.latitude;
  msg.gps.altitude = gps.altitude;
  msg.gps.error = gps.error;
  msg.gps.bearing = gps.bearing;

  if (data.isStereo()) {
    const std::vector<rtabmap::StereoCameraModel>& stereo = data.stereoCameraModels();
    for (const rtabmap::StereoCameraModel& model : stereo) addCamera(msg, model.left());
    msg.baseline = static_cast<float>(stereo.front().baseline());
    warnIfBaselinesDiffer(stereo, node.id());
  } else {
    for (const rtabmap::CameraModel& model : data.cameraModels()) addCamera(msg, model);
  }

  if (withSensorData) {
    rtabmap::SensorData compressed = data;
    const bool missing = (compressed.imageCompressed().empty() && !data.imageRaw().empty()) ||
                         (compressed.depthOrRightCompressed().empty() && !data.depthOrRightRaw().empty()) ||
                         (compressed.laserScanCompressed().empty() && !data.laserScanRaw().empty()) ||
                         (compressed.userDataCompressed().empty() && !data.userDataRaw().empty());
    if (missing) compressed.compress(".jpg");
    msg.image = compressed.imageCompressed();
    msg.depth = compressed.depthOrRightCompressed();
    msg.laserScan = compressed.laserScanCompressed();
    msg.userData = compressed.userDataCompressed();
    const rtabmap::SensorData::ScanInfo scan = compressed.laserScanInfo();
    msg.laserScanMaxPts = scan.maxPoints;
    msg.laserScanMaxRange = static_cast<float>(scan.rangeMax);
    msg.laserScanFormat = static_cast<int32_t>(scan.format);
    msg.laserScanLocalTransform = transformToMsg(scan.localTransform);

    const rtabmap::LocalGrid& grid = data.localGrid();
    msg.grid_ground = blobOf(grid.ground);
    msg.grid_obstacles = blobOf(grid.obstacles);
    msg.grid_empty_cells = blobOf(grid.empty);
    msg.grid_cell_size = grid.cellSize;
    msg.grid_view_point.x = grid.viewPoint.x();
    msg.grid_view_point.y = grid.viewPoint.y();
    msg.grid_view_point.z = grid.viewPoint.z();
  }

  const std::vector<int> wordIds = node.wordIdPerKeypoint();
  msg.wordIds.assign(wordIds.begin(), wordIds.end());
  msg.wordKpts = keypointsToMsg(node.getWordsKpts());
  msg.wordPts = pointsToMsg(node.getWords3());
  msg.wordDescriptors = descriptorsToMsg(node.getWordsDescriptors());
  return msg;
}

std::optional<rtabmap::Signature> nodeDataFromMsg(const rtabmap_ros::NodeData& msg, std::string* error) {
  const std::string what = "NodeData of node " + std::to_string(msg.id);
  std::string why;
  rtabmap::SensorData data;
  data.setStamp(msg.stamp);
  if (!setCameras(msg, data, &why)) return detail::fail(error, what + ": " + why);
  data.setCompressed(msg.image, msg.depth, msg.laserScan, msg.userData);
  if (!msg.laserScan.empty()) {
    if (msg.laserScanFormat <= rtabmap::LaserScan::kUnknown || msg.laserScanFormat > rtabmap::LaserScan::kXYZRGBNormal) {
      return detail::fail(error, what + ": unknown laser scan format " + std::to_string(msg.laserScanFormat));
    }
    rtabmap::SensorData::ScanInfo scan;
    scan.format = static_cast<rtabmap::LaserScan::Format>(msg.laserScanFormat);
    scan.maxPoints = msg.laserScanMaxPts;
    scan.rangeMax = msg.laserScanMaxRange;
    scan.localTransform = transformFromMsg(msg.laserScanLocalTransform);
    if (scan.localTransform.isNull()) scan.localTransform = rtabmap::Transform::Identity();
    data.setLaserScanInfo(scan);
  }
  rtabmap::GPS gps;
  gps.stamp = msg.gps.stamp;
  gps.longitude = msg.gps.longitude;
  gps.latitude = msg.gps.latitude;
  gps.altitude = msg.gps.altitude;
  gps.error = msg.gps.error;
  gps.bearing = msg.gps.bearing;
  data.setGPS(gps);

  rtabmap::LocalGrid grid;
  if (!matOfBlob(msg.grid_ground, "grid_ground", grid.ground, &why) ||
      !matOfBlob(msg.grid_obstacles, "grid_obstacles", grid.obstacles, &why) ||
      !matOfBlob(msg.grid_empty_cells, "grid_empty_cells", grid.empty, &why)) {
    return detail::fail(error, what + ": " + why);
  }
  grid.cellSize = msg.grid_cell_size;
  grid.viewPoint = Eigen::Vector3f(msg.grid_view_point.x, msg.grid_view_point.y, msg.grid_view_point.z);
  data.setLocalGrid(grid);

  rtabmap::Signature node(msg.id, msg.mapId, msg.weight, msg.stamp, msg.label, transformFromPoseMsg(msg.pose),
                          transformFromPoseMsg(msg.groundTruthPose), data);
  if (!msg.wordIds.empty() || !msg.wordKpts.empty()) {
    const size_t n = msg.wordIds.size();
    if ((!msg.wordKpts.empty() && msg.wordKpts.size() != n) || (!msg.wordPts.empty() && msg.wordPts.size() != n)) {
      return detail::fail(error, what + ": " + std::to_string(n) + " word ids, " + std::to_string(msg.wordKpts.size()) +
                                     " keypoints and " + std::to_string(msg.wordPts.size()) + " 3D points");
    }
    std::optional<cv::Mat> descriptors = descriptorsFromMsg(msg.wordDescriptors, static_cast<int>(n), &why);
    if (!descriptors) return detail::fail(error, what + ": words: " + why);
    std::multimap<int, int> words;
    for (size_t i = 0; i < n; ++i) words.emplace(msg.wordIds[i], static_cast<int>(i));
    try {
      node.setWords(words, keypointsFromMsg(msg.wordKpts), pointsFromMsg(msg.wordPts), *descriptors);
    } catch (const std::exception& e) {
      return detail::fail(error, what + ": words: " + e.what());
    }
  }
  return node;
}

rtabmap_ros::MapData mapDataToMsg(const std::map<int, rtabmap::Transform>& poses,
                                  const std::multimap<int, rtabmap::Link>& links,
                                  const std::map<int, rtabmap::Signature>& nodes,
                                  const rtabmap::Transform& mapToOdom, const std_msgs::Header& header,
                                  bool withSensorData) {
  rtabmap_ros::MapData msg;
  msg.header = header;
  msg.graph = mapGraphToMsg(poses, links, mapToOdom, header);
  msg.nodes.reserve(nodes.size());
  for (const auto& entry : nodes) msg.nodes.push_back(nodeDataToMsg(entry.second, withSensorData));
  return msg;
}

std::optional<MapData> mapDataFromMsg(const rtabmap_ros::MapData& msg, std::string* error) {
  std::optional<MapGraph> graph = mapGraphFromMsg(msg.graph, error);
  if (!graph) return std::nullopt;
  MapData out;
  out.graph = std::move(*graph);
  for (const rtabmap_ros::NodeData& n : msg.nodes) {
    std::optional<rtabmap::Signature> node = nodeDataFromMsg(n, error);
    if (!node) return std::nullopt;
    out.nodes[node->id()] = std::move(*node);
  }
  for (const auto& [from, link] : out.graph.links) {
    auto it = out.nodes.find(from);
    if (it != out.nodes.end()) it->second.addLink(link);
  }
  return out;
}

}  // namespace rtabmap_conversions

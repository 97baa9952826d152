#include "rtabmap_slam_node/MapsMessages.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rtabmap_slam_node {
namespace {

sensor_msgs::PointField floatField(const std::string& name, uint32_t offset) {
  sensor_msgs::PointField f;
  f.name = name;
  f.offset = offset;
  f.datatype = sensor_msgs::PointField::FLOAT32;
  f.count = 1;
  return f;
}

// Blue (t = 0) to red (t = 1) through cyan, green and yellow: hue 240 deg down to 0.
std_msgs::ColorRGBA heightColour(float t) {
  const float h = (1.0f - std::clamp(t, 0.0f, 1.0f)) * 4.0f;  // sextant of the hue circle, 0..4
  const int i = std::min(3, static_cast<int>(h));
  const float f = h - static_cast<float>(i);
  std_msgs::ColorRGBA c;
  c.a = 1.0f;
  switch (i) {
    case 0: c.r = 1.0f; c.g = f; break;          // red -> yellow
    case 1: c.r = 1.0f - f; c.g = 1.0f; break;   // yellow -> green
    case 2: c.g = 1.0f; c.b = f; break;          // green -> cyan
    default: c.g = 1.0f - f; c.b = 1.0f; break;  // cyan -> blue
  }
  return c;
}

visualization_msgs::Marker cubes(const rtabmap::Cloud& voxels, const std::string& ns, float size, float zMin,
                                 float zMax, const std_msgs::Header& header) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = 0;
  m.type = visualization_msgs::Marker::CUBE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = size;
  m.color.a = 1.0f;  // rviz uses the per-point colours; the marker's alpha still applies
  const bool coloured = voxels.hasColors();
  const float range = zMax > zMin ? zMax - zMin : 1.0f;
  m.points.reserve(voxels.size());
  m.colors.reserve(voxels.size());
  for (size_t i = 0; i < voxels.size(); ++i) {
    const cv::Point3f& p = voxels.points[i];
    geometry_msgs::Point q;
    q.x = p.x;
    q.y = p.y;
    q.z = p.z;
    m.points.push_back(q);
    std_msgs::ColorRGBA c = heightColour((p.z - zMin) / range);
    if (coloured) {
      c.r = voxels.colors[i][0] / 255.0f;
      c.g = voxels.colors[i][1] / 255.0f;
      c.b = voxels.colors[i][2] / 255.0f;
    }
    m.colors.push_back(c);
  }
  return m;
}

}  // namespace

sensor_msgs::PointCloud2 cloudToMsg(const rtabmap::Cloud& cloud, const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 msg;
  msg.header = header;
  msg.height = 1;
  msg.width = static_cast<uint32_t>(cloud.size());
  msg.is_bigendian = false;
  msg.is_dense = true;  // the maps hold finite points only
  const bool rgb = cloud.hasColors();
  msg.fields = {floatField("x", 0), floatField("y", 4), floatField("z", 8)};
  if (rgb) msg.fields.push_back(floatField("rgb", 12));
  msg.point_step = rgb ? 16 : 12;
  msg.row_step = msg.point_step * msg.width;
  msg.data.resize(static_cast<size_t>(msg.row_step));
  uint8_t* out = msg.data.data();
  for (size_t i = 0; i < cloud.size(); ++i, out += msg.point_step) {
    const float xyz[3] = {cloud.points[i].x, cloud.points[i].y, cloud.points[i].z};
    std::memcpy(out, xyz, sizeof(xyz));
    if (rgb) {
      const float packed = rtabmap::packRgb(cloud.colors[i]);
      std::memcpy(out + 12, &packed, sizeof(packed));
    }
  }
  return msg;
}

rtabmap_ros::OctoMap octoMapToMsg(const rtabmap::OctoMapMessage& octomap, const std_msgs::Header& header) {
  rtabmap_ros::OctoMap msg;
  msg.header = header;
  msg.binary = octomap.binary;
  msg.id = octomap.id;
  msg.resolution = octomap.resolution;
  msg.data = octomap.data;
  return msg;
}

rtabmap::Cloud occupiedVoxels(const rtabmap::OctoMapCells& cells) {
  rtabmap::Cloud out = cells.obstacles;
  out.append(cells.ground);
  return out;
}

visualization_msgs::MarkerArray occupiedCellsMarkers(const rtabmap::OctoMapCells& cells,
                                                     const std_msgs::Header& header) {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker clear;
  clear.header = header;
  clear.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(clear);
  float zMin = INFINITY, zMax = -INFINITY;
  for (const rtabmap::Cloud* c : {&cells.obstacles, &cells.ground}) {
    for (const cv::Point3f& p : c->points) {
      zMin = std::min(zMin, p.z);
      zMax = std::max(zMax, p.z);
    }
  }
  if (!cells.obstacles.empty()) {
    out.markers.push_back(cubes(cells.obstacles, "obstacles", cells.voxelSize, zMin, zMax, header));
  }
  if (!cells.ground.empty()) out.markers.push_back(cubes(cells.ground, "ground", cells.voxelSize, zMin, zMax, header));
  return out;
}

}  // namespace rtabmap_slam_node

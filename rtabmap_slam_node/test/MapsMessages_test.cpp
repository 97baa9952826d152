#include "rtabmap_slam_node/MapsMessages.h"

#include <gtest/gtest.h>

#include <cstring>

namespace rtabmap_slam_node {
namespace {

std_msgs::Header mapHeader() {
  std_msgs::Header h;
  h.frame_id = "map";
  h.stamp = ros::Time(12, 5);
  return h;
}

float floatAt(const sensor_msgs::PointCloud2& msg, size_t point, const std::string& field) {
  for (const sensor_msgs::PointField& f : msg.fields) {
    if (f.name != field) continue;
    EXPECT_EQ(f.datatype, sensor_msgs::PointField::FLOAT32);
    float v = 0.0f;
    std::memcpy(&v, msg.data.data() + point * msg.point_step + f.offset, sizeof(v));
    return v;
  }
  ADD_FAILURE() << "no field " << field;
  return 0.0f;
}

TEST(MapsMessages, CloudWithoutColourHasXyzOnly) {
  rtabmap::Cloud c;
  c.push_back(cv::Point3f(1, 2, 3));
  c.push_back(cv::Point3f(-4, 5.5f, 0));
  const sensor_msgs::PointCloud2 msg = cloudToMsg(c, mapHeader());
  EXPECT_EQ(msg.header.frame_id, "map");
  EXPECT_EQ(msg.header.stamp, ros::Time(12, 5));
  EXPECT_EQ(msg.width, 2u);
  EXPECT_EQ(msg.height, 1u);
  ASSERT_EQ(msg.fields.size(), 3u);
  EXPECT_EQ(msg.point_step, 12u);
  EXPECT_EQ(msg.row_step, 24u);
  ASSERT_EQ(msg.data.size(), 24u);
  EXPECT_FALSE(msg.is_bigendian);
  EXPECT_FLOAT_EQ(floatAt(msg, 1, "x"), -4.0f);
  EXPECT_FLOAT_EQ(floatAt(msg, 1, "y"), 5.5f);
  EXPECT_FLOAT_EQ(floatAt(msg, 0, "z"), 3.0f);
}

TEST(MapsMessages, CloudColoursArePackedAsPclRgb) {
  rtabmap::Cloud c;
  c.push_back(cv::Point3f(1, 2, 3), cv::Vec3b(255, 128, 1));
  const sensor_msgs::PointCloud2 msg = cloudToMsg(c, mapHeader());
  ASSERT_EQ(msg.fields.size(), 4u);
  EXPECT_EQ(msg.fields[3].name, "rgb");
  EXPECT_EQ(msg.point_step, 16u);
  const float rgb = floatAt(msg, 0, "rgb");
  uint32_t bits = 0;
  std::memcpy(&bits, &rgb, sizeof(bits));
  EXPECT_EQ(bits, 0x00FF8001u);  // 0x00RRGGBB
  EXPECT_FLOAT_EQ(floatAt(msg, 0, "y"), 2.0f);
}

TEST(MapsMessages, EmptyCloudIsAValidEmptyMessage) {
  const sensor_msgs::PointCloud2 msg = cloudToMsg(rtabmap::Cloud(), mapHeader());
  EXPECT_EQ(msg.width, 0u);
  EXPECT_TRUE(msg.data.empty());
  EXPECT_EQ(msg.fields.size(), 3u);
}

TEST(MapsMessages, OctoMapFieldsArePassedThrough) {
  rtabmap::OctoMapMessage m;
  m.binary = false;
  m.id = "ColorOcTree";
  m.resolution = 0.05;
  m.data = {1, -2, 3};
  const rtabmap_ros::OctoMap msg = octoMapToMsg(m, mapHeader());
  EXPECT_FALSE(msg.binary);
  EXPECT_EQ(msg.id, "ColorOcTree");
  EXPECT_DOUBLE_EQ(msg.resolution, 0.05);
  EXPECT_EQ(msg.data, m.data);
  EXPECT_EQ(msg.header.frame_id, "map");
}

TEST(MapsMessages, OccupiedVoxelsAreObstaclesAndGround) {
  rtabmap::OctoMapCells cells;
  cells.obstacles.push_back(cv::Point3f(1, 0, 1));
  cells.ground.push_back(cv::Point3f(0, 0, 0));
  cells.ground.push_back(cv::Point3f(0.05f, 0, 0));
  cells.empty.push_back(cv::Point3f(0, 0, 0.5f));
  const rtabmap::Cloud occupied = occupiedVoxels(cells);
  ASSERT_EQ(occupied.size(), 3u);
  EXPECT_FLOAT_EQ(occupied.points[0].z, 1.0f);
}

TEST(MapsMessages, OccupiedCellsAreCubesColouredByHeightWithoutMapColours) {
  rtabmap::OctoMapCells cells;
  cells.voxelSize = 0.1f;
  cells.obstacles.push_back(cv::Point3f(1, 0, 2));  // highest: red
  cells.obstacles.push_back(cv::Point3f(1, 0, 1));  // middle: green
  cells.ground.push_back(cv::Point3f(0, 0, 0));     // lowest: blue
  const visualization_msgs::MarkerArray a = occupiedCellsMarkers(cells, mapHeader());
  ASSERT_EQ(a.markers.size(), 3u);
  EXPECT_EQ(a.markers[0].action, visualization_msgs::Marker::DELETEALL);
  const visualization_msgs::Marker& obstacles = a.markers[1];
  EXPECT_EQ(obstacles.ns, "obstacles");
  EXPECT_EQ(obstacles.type, visualization_msgs::Marker::CUBE_LIST);
  EXPECT_FLOAT_EQ(obstacles.scale.x, 0.1f);
  EXPECT_EQ(obstacles.header.frame_id, "map");
  ASSERT_EQ(obstacles.points.size(), 2u);
  ASSERT_EQ(obstacles.colors.size(), 2u);
  EXPECT_FLOAT_EQ(obstacles.colors[0].r, 1.0f);
  EXPECT_FLOAT_EQ(obstacles.colors[0].g, 0.0f);
  EXPECT_FLOAT_EQ(obstacles.colors[0].b, 0.0f);
  EXPECT_FLOAT_EQ(obstacles.colors[1].g, 1.0f);
  EXPECT_FLOAT_EQ(obstacles.colors[1].r, 0.0f);
  const visualization_msgs::Marker& ground = a.markers[2];
  EXPECT_EQ(ground.ns, "ground");
  ASSERT_EQ(ground.colors.size(), 1u);
  EXPECT_FLOAT_EQ(ground.colors[0].b, 1.0f);
  EXPECT_FLOAT_EQ(ground.colors[0].g, 0.0f);
  EXPECT_FLOAT_EQ(ground.colors[0].a, 1.0f);
}

TEST(MapsMessages, OccupiedCellsKeepTheMapColoursAndSkipEmptyKinds) {
  rtabmap::OctoMapCells cells;
  cells.voxelSize = 0.05f;
  cells.obstacles.push_back(cv::Point3f(1, 0, 2), cv::Vec3b(0, 51, 255));
  const visualization_msgs::MarkerArray a = occupiedCellsMarkers(cells, mapHeader());
  ASSERT_EQ(a.markers.size(), 2u) << "no ground marker without ground voxels";
  ASSERT_EQ(a.markers[1].colors.size(), 1u);
  EXPECT_FLOAT_EQ(a.markers[1].colors[0].r, 0.0f);
  EXPECT_FLOAT_EQ(a.markers[1].colors[0].g, 0.2f);
  EXPECT_FLOAT_EQ(a.markers[1].colors[0].b, 1.0f);
  EXPECT_DOUBLE_EQ(a.markers[1].points[0].z, 2.0);
}

}  // namespace
}  // namespace rtabmap_slam_node

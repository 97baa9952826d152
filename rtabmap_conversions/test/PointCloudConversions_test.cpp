#include "rtabmap_conversions/PointCloudConversions.h"

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl_conversions/pcl_conversions.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "TestHelpers.h"

using namespace rtabmap_conversions;
using rtabmap::LaserScan;
using rtabmap::Transform;
using rtabmap_conversions::test::sameBits;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

LaserScan makeScan(LaserScan::Format format, int n = 50) {
  const int cn = LaserScan::channels(format);
  cv::Mat data(1, n, CV_32FC(cn));
  cv::RNG rng(11);
  rng.fill(data, cv::RNG::UNIFORM, -20.0, 20.0);
  if (LaserScan::hasRGB(format)) {
    const int rgbChannel = LaserScan::is2d(format) ? 2 : 3;
    for (int i = 0; i < n; ++i) {
      const uint32_t packed = 0x00102030u + uint32_t(i) * 0x010101u;
      std::memcpy(data.ptr<float>(0) + i * cn + rgbChannel, &packed, 4);
    }
  }
  return LaserScan(data, 2 * n, 0.5, 80.0, format, Transform(0, 0, 1.8, 0, 0, 0.1));
}

std_msgs::Header header(const std::string& frame = "velodyne") {
  std_msgs::Header h;
  h.frame_id = frame;
  h.stamp = ros::Time(10, 500);
  return h;
}

}  // namespace

TEST(PointCloudConversions, Every3DFormatRoundTripsBitExactly) {
  for (LaserScan::Format f : {LaserScan::kXYZ, LaserScan::kXYZI, LaserScan::kXYZRGB, LaserScan::kXYZNormal,
                              LaserScan::kXYZINormal, LaserScan::kXYZRGBNormal}) {
    const LaserScan scan = makeScan(f);
    const sensor_msgs::PointCloud2 msg = laserScanToCloudMsg(scan, header());
    EXPECT_EQ(msg.width, 50u);
    EXPECT_EQ(msg.height, 1u);
    EXPECT_EQ(msg.header.frame_id, "velodyne");
    std::string error;
    const std::optional<LaserScan> back = laserScanFromCloudMsg(msg, scan.localTransform(), &error, 0.5, 80.0);
    ASSERT_TRUE(back) << LaserScan::formatName(f) << ": " << error;
    EXPECT_EQ(back->format(), f) << LaserScan::formatName(f);
    EXPECT_TRUE(sameBits(back->data(), scan.data())) << LaserScan::formatName(f);
    EXPECT_EQ(back->localTransform(), scan.localTransform());
    EXPECT_EQ(back->rangeMax(), 80.0);
  }
}

TEST(PointCloudConversions, PlanarScansComeBackWithZeroZ) {
  for (auto [planar, spatial] : {std::pair{LaserScan::kXY, LaserScan::kXYZ}, std::pair{LaserScan::kXYI, LaserScan::kXYZI},
                                 std::pair{LaserScan::kXYNormal, LaserScan::kXYZNormal}}) {
    const LaserScan scan = makeScan(planar, 20);
    const std::optional<LaserScan> back = laserScanFromCloudMsg(laserScanToCloudMsg(scan, header("laser")));
    ASSERT_TRUE(back);
    EXPECT_EQ(back->format(), spatial);
    const int cin = scan.data().channels(), cout = back->data().channels();
    for (int i = 0; i < 20; ++i) {
      const float* a = scan.data().ptr<float>(0) + i * cin;
      const float* b = back->data().ptr<float>(0) + i * cout;
      EXPECT_EQ(a[0], b[0]);
      EXPECT_EQ(a[1], b[1]);
      EXPECT_EQ(b[2], 0.0f);
      for (int k = 2; k < cin; ++k) EXPECT_EQ(a[k], b[k + 1]);
    }
  }
}

TEST(PointCloudConversions, ReadsPclCloudsWithPaddingAndDropsNaNs) {
  // PCL's PointXYZRGBNormal has padding between fields and an organised cloud marks holes with NaN.
  pcl::PointCloud<pcl::PointXYZRGBNormal> cloud(4, 3);
  for (size_t i = 0; i < cloud.size(); ++i) {
    auto& p = cloud[i];
    p.x = float(i);
    p.y = float(i) * 2.0f;
    p.z = -float(i);
    p.r = uint8_t(i * 10);
    p.g = uint8_t(i * 20);
    p.b = uint8_t(i * 5);
    p.normal_x = 0.0f;
    p.normal_y = 0.6f;
    p.normal_z = 0.8f;
  }
  cloud[5].x = kNaN;
  cloud[7].z = std::numeric_limits<float>::infinity();
  sensor_msgs::PointCloud2 msg;
  pcl::toROSMsg(cloud, msg);
  std::string error;
  const std::optional<LaserScan> scan = laserScanFromCloudMsg(msg, Transform::Identity(), &error);
  ASSERT_TRUE(scan) << error;
  EXPECT_EQ(scan->format(), LaserScan::kXYZRGBNormal);
  EXPECT_EQ(scan->size(), 10);
  EXPECT_EQ(scan->maxPoints(), 12);
  // Point 6 of the cloud is the 6th kept (5 dropped before it).
  const float* p = scan->data().ptr<float>(0) + 5 * 7;
  EXPECT_EQ(p[0], 6.0f);
  EXPECT_EQ(p[1], 12.0f);
  uint32_t rgb;
  std::memcpy(&rgb, &p[3], 4);
  EXPECT_EQ(rgb & 0xFFFFFFu, (60u << 16) | (120u << 8) | 30u);
  EXPECT_FLOAT_EQ(p[5], 0.6f);

  // And the other way: our message read by PCL.
  pcl::PointCloud<pcl::PointXYZINormal> fromOurs;
  pcl::fromROSMsg(laserScanToCloudMsg(makeScan(LaserScan::kXYZINormal, 5), header()), fromOurs);
  const LaserScan ref = makeScan(LaserScan::kXYZINormal, 5);
  ASSERT_EQ(fromOurs.size(), 5u);
  EXPECT_EQ(fromOurs[4].intensity, ref.data().ptr<float>(0)[4 * 7 + 3]);
  EXPECT_EQ(fromOurs[4].normal_z, ref.data().ptr<float>(0)[4 * 7 + 6]);
}

TEST(PointCloudConversions, ReadsOtherFieldTypes) {
  // Like some lidar drivers: float64 coordinates and uint16 intensity, packed, 26 bytes a point.
  sensor_msgs::PointCloud2 msg;
  msg.header = header();
  auto field = [](const char* name, uint32_t offset, uint8_t type) {
    sensor_msgs::PointField f;
    f.name = name;
    f.offset = offset;
    f.datatype = type;
    f.count = 1;
    return f;
  };
  msg.fields = {field("x", 0, sensor_msgs::PointField::FLOAT64), field("y", 8, sensor_msgs::PointField::FLOAT64),
                field("z", 16, sensor_msgs::PointField::FLOAT64), field("intensity", 24, sensor_msgs::PointField::UINT16)};
  msg.point_step = 26;
  msg.width = 2;
  msg.height = 1;
  msg.row_step = 52;
  msg.data.resize(52);
  const double xyz[2][3] = {{1.5, -2.25, 0.125}, {100.0, 0.0, -3.0}};
  const uint16_t intensity[2] = {7, 65000};
  for (int i = 0; i < 2; ++i) {
    std::memcpy(&msg.data[i * 26], xyz[i], 24);
    std::memcpy(&msg.data[i * 26 + 24], &intensity[i], 2);
  }
  const std::optional<LaserScan> scan = laserScanFromCloudMsg(msg);
  ASSERT_TRUE(scan);
  EXPECT_EQ(scan->format(), LaserScan::kXYZI);
  const float* p = scan->data().ptr<float>(0);
  EXPECT_EQ(p[0], 1.5f);
  EXPECT_EQ(p[1], -2.25f);
  EXPECT_EQ(p[2], 0.125f);
  EXPECT_EQ(p[3], 7.0f);
  EXPECT_EQ(p[7], 65000.0f);
}

TEST(PointCloudConversions, MalformedCloudsAreErrors) {
  std::string error;
  const sensor_msgs::PointCloud2 good = laserScanToCloudMsg(makeScan(LaserScan::kXYZI, 10), header());

  sensor_msgs::PointCloud2 noZ = good;
  noZ.fields.erase(noZ.fields.begin() + 2);
  EXPECT_FALSE(laserScanFromCloudMsg(noZ, Transform::Identity(), &error));
  EXPECT_NE(error.find("no x, y and z"), std::string::npos) << error;
  EXPECT_NE(error.find("intensity"), std::string::npos) << error;  // lists the fields it has

  sensor_msgs::PointCloud2 shortData = good;
  shortData.data.resize(shortData.data.size() - 4);
  EXPECT_FALSE(laserScanFromCloudMsg(shortData, Transform::Identity(), &error));
  EXPECT_NE(error.find("do not fit"), std::string::npos) << error;

  sensor_msgs::PointCloud2 badOffset = good;
  badOffset.fields[3].offset = 14;  // a float at 14 runs past the 16-byte point
  EXPECT_FALSE(laserScanFromCloudMsg(badOffset, Transform::Identity(), &error));
  EXPECT_NE(error.find("'intensity'"), std::string::npos) << error;

  sensor_msgs::PointCloud2 bigEndian = good;
  bigEndian.is_bigendian = true;
  EXPECT_FALSE(laserScanFromCloudMsg(bigEndian, Transform::Identity(), &error));
  EXPECT_NE(error.find("big-endian"), std::string::npos) << error;

  sensor_msgs::PointCloud2 lyingWidth = good;
  lyingWidth.width = 1000;  // row_step no longer covers the points
  EXPECT_FALSE(laserScanFromCloudMsg(lyingWidth, Transform::Identity(), &error));

  sensor_msgs::PointCloud2 empty = good;
  empty.width = 0;
  empty.data.clear();
  empty.row_step = 0;
  const std::optional<LaserScan> none = laserScanFromCloudMsg(empty);
  ASSERT_TRUE(none);  // an empty cloud is a valid (empty) scan
  EXPECT_TRUE(none->empty());
}

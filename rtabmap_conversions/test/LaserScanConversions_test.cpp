#include "rtabmap_conversions/LaserScanConversions.h"

#include <gtest/gtest.h>
#include <laser_geometry/laser_geometry.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <cmath>
#include <limits>

using namespace rtabmap_conversions;
using rtabmap::LaserScan;
using rtabmap::Transform;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A URG-like scan: 240 degrees, 0.36 degree steps, ranges with holes of every kind.
sensor_msgs::LaserScan urgScan(bool intensities) {
  sensor_msgs::LaserScan msg;
  msg.header.frame_id = "laser";
  msg.header.stamp = ros::Time(50, 0);
  msg.angle_increment = static_cast<float>(0.36 * M_PI / 180.0);
  msg.angle_min = static_cast<float>(-120.0 * M_PI / 180.0);
  const int beams = 667;
  msg.angle_max = msg.angle_min + msg.angle_increment * (beams - 1);
  msg.range_min = 0.02f;
  msg.range_max = 5.6f;
  for (int i = 0; i < beams; ++i) {
    float r = 0.5f + 4.0f * float(i % 97) / 97.0f;
    if (i % 50 == 3) r = kInf;   // no return
    if (i % 50 == 7) r = kNaN;   // invalid
    if (i % 50 == 11) r = 7.0f;  // beyond range_max
    if (i % 50 == 13) r = 0.01f; // below range_min
    msg.ranges.push_back(r);
    if (intensities) msg.intensities.push_back(float(100 + i));
  }
  return msg;
}

bool usable(float r, const sensor_msgs::LaserScan& m) { return std::isfinite(r) && r >= m.range_min && r <= m.range_max; }

}  // namespace

TEST(LaserScanConversions, ScanKeepsValidBeamsAndTheBeamGeometry) {
  const sensor_msgs::LaserScan msg = urgScan(false);
  const Transform local(0.2, 0.0, 0.3, 0.0, 0.0, 0.1);
  std::string error;
  const std::optional<LaserScan> scan = laserScanFromMsg(msg, local, &error);
  ASSERT_TRUE(scan) << error;
  int valid = 0;
  for (float r : msg.ranges) valid += usable(r, msg) ? 1 : 0;
  EXPECT_EQ(scan->size(), valid);
  EXPECT_EQ(scan->maxPoints(), int(msg.ranges.size()));
  EXPECT_EQ(scan->format(), LaserScan::kXY);
  EXPECT_EQ(scan->localTransform(), local);
  EXPECT_FLOAT_EQ(float(scan->angleMin()), msg.angle_min);
  EXPECT_FLOAT_EQ(float(scan->angleIncrement()), msg.angle_increment);
  EXPECT_DOUBLE_EQ(scan->rangeMax(), double(msg.range_max));
}

TEST(LaserScanConversions, RangesAndIntensitiesRoundTrip) {
  const sensor_msgs::LaserScan msg = urgScan(true);
  const std::optional<LaserScan> scan = laserScanFromMsg(msg);
  ASSERT_TRUE(scan);
  EXPECT_EQ(scan->format(), LaserScan::kXYI);
  std::string error;
  const std::optional<sensor_msgs::LaserScan> back = laserScanToMsg(*scan, msg.header, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->header.frame_id, "laser");
  EXPECT_EQ(back->header.stamp, msg.header.stamp);
  EXPECT_FLOAT_EQ(back->angle_min, msg.angle_min);
  EXPECT_NEAR(back->angle_max, msg.angle_max, 1e-6);
  EXPECT_FLOAT_EQ(back->angle_increment, msg.angle_increment);
  EXPECT_FLOAT_EQ(back->range_min, msg.range_min);
  EXPECT_FLOAT_EQ(back->range_max, msg.range_max);
  ASSERT_EQ(back->ranges.size(), msg.ranges.size());
  ASSERT_EQ(back->intensities.size(), msg.ranges.size());
  for (size_t i = 0; i < msg.ranges.size(); ++i) {
    if (usable(msg.ranges[i], msg)) {
      EXPECT_NEAR(back->ranges[i], msg.ranges[i], 2e-6f * msg.ranges[i]) << "beam " << i;
      EXPECT_EQ(back->intensities[i], msg.intensities[i]) << "beam " << i;
    } else {
      EXPECT_EQ(back->ranges[i], kInf) << "beam " << i << " had " << msg.ranges[i];  // REP-117 no return
    }
  }
}

TEST(LaserScanConversions, ClockwiseScannersWork) {
  sensor_msgs::LaserScan msg = urgScan(false);
  msg.ranges.resize(300);  // 3 rad: bearings stay distinct (a scan over a full turn would not)
  msg.angle_min = 2.0f;
  msg.angle_increment = -0.01f;
  msg.angle_max = msg.angle_min + msg.angle_increment * float(msg.ranges.size() - 1);
  const std::optional<LaserScan> scan = laserScanFromMsg(msg);
  ASSERT_TRUE(scan);
  const std::optional<sensor_msgs::LaserScan> back = laserScanToMsg(*scan, msg.header);
  ASSERT_TRUE(back);
  ASSERT_EQ(back->ranges.size(), msg.ranges.size());
  for (size_t i = 0; i < msg.ranges.size(); ++i) {
    if (usable(msg.ranges[i], msg)) EXPECT_NEAR(back->ranges[i], msg.ranges[i], 1e-5f) << i;
  }
}

TEST(LaserScanConversions, AllNoReturnScanStaysAScan) {
  sensor_msgs::LaserScan msg = urgScan(false);
  std::fill(msg.ranges.begin(), msg.ranges.end(), kInf);
  const std::optional<LaserScan> scan = laserScanFromMsg(msg);
  ASSERT_TRUE(scan);
  EXPECT_TRUE(scan->empty());
  EXPECT_TRUE(scan->hasBeamGeometry());
  const std::optional<sensor_msgs::LaserScan> back = laserScanToMsg(*scan, msg.header);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->ranges, msg.ranges);
}

TEST(LaserScanConversions, MalformedScansAreErrors) {
  std::string error;
  const sensor_msgs::LaserScan good = urgScan(true);
  auto expectError = [&](sensor_msgs::LaserScan msg, const std::string& words) {
    error.clear();
    EXPECT_FALSE(laserScanFromMsg(msg, Transform::Identity(), &error)) << words;
    EXPECT_NE(error.find(words), std::string::npos) << error;
  };
  sensor_msgs::LaserScan m = good;
  m.angle_increment = 0.0f;
  expectError(m, "beam geometry");
  m = good;
  m.angle_min = kNaN;
  expectError(m, "beam geometry");
  m = good;
  m.ranges.resize(300);
  expectError(m, "300 ranges");
  m = good;
  m.ranges.clear();
  expectError(m, "no ranges");
  m = good;
  m.intensities.pop_back();
  expectError(m, "intensities");
  m = good;
  m.range_max = 0.0f;
  expectError(m, "range limits");
  m = good;
  m.angle_max = m.angle_min - 1.0f;  // angles going the other way from the increment
  expectError(m, "ranges");
  m = good;
  m.angle_max += m.angle_increment;  // one beam of slack is tolerated (drivers disagree)
  EXPECT_TRUE(laserScanFromMsg(m));
}

TEST(LaserScanConversions, ScansWithoutBeamsCannotBecomeLaserScanMessages) {
  std::string error;
  cv::Mat xyz(1, 3, CV_32FC3, cv::Scalar(1, 2, 3));
  EXPECT_FALSE(laserScanToMsg(LaserScan(xyz, 3, 0, 10, LaserScan::kXYZ), std_msgs::Header(), &error));
  EXPECT_NE(error.find("PointCloud2"), std::string::npos) << error;
  cv::Mat xy(1, 3, CV_32FC2, cv::Scalar(1, 2));
  EXPECT_FALSE(laserScanToMsg(LaserScan(xy, 3, 0, 10, LaserScan::kXY), std_msgs::Header(), &error));
  EXPECT_NE(error.find("beam geometry"), std::string::npos) << error;
}

// The classic path projects scans with laser_geometry: ours must give the same points, so a
// map made from either agrees (same beams kept, same positions).
TEST(LaserScanConversions, SamePointsAsLaserGeometry) {
  const sensor_msgs::LaserScan msg = urgScan(true);
  sensor_msgs::PointCloud2 reference;
  laser_geometry::LaserProjection().projectLaser(msg, reference, -1.0, laser_geometry::channel_option::Intensity);
  std::string error;
  const std::optional<LaserScan> scan = laserScanFromMsg(msg, Transform::Identity(), &error);
  ASSERT_TRUE(scan) << error;
  ASSERT_EQ(size_t(scan->size()), size_t(reference.width) * reference.height);
  sensor_msgs::PointCloud2ConstIterator<float> it(reference, "x"), intensity(reference, "intensity");
  for (int i = 0; i < scan->size(); ++i, ++it, ++intensity) {
    const float* p = scan->data().ptr<float>(0) + 3 * i;
    EXPECT_NEAR(p[0], it[0], 1e-5) << "point " << i;
    EXPECT_NEAR(p[1], it[1], 1e-5) << "point " << i;
    EXPECT_FLOAT_EQ(p[2], *intensity) << "point " << i;
  }
}

#include "rtabmap_conversions/Deskewing.h"

#include <gtest/gtest.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "rtabmap_conversions/LaserScanConversions.h"
#include "rtabmap_conversions/PointCloudConversions.h"
#include "TestHelpers.h"

using namespace rtabmap_conversions;
using rtabmap_conversions::test::setTransform;
using rtabmap::Transform;

namespace {

// A robot in a 10 m x 10 m square room (walls at x, y = +-5), starting at the room's centre at
// kStamp, driving at 1 m/s while turning at 2 rad/s; a 360-beam lidar mounted at kMount
// sweeps a full turn in 0.1 s. Each beam is measured at its own time, from where the robot is
// then: taken as one rigid scan, the walls bend by tens of centimetres.
constexpr double kStamp = 100.0;
constexpr double kSweep = 0.1;
constexpr int kBeams = 360;
constexpr double kSpeed = 1.0;
constexpr double kTurnRate = 2.0;
constexpr double kHalfRoom = 5.0;
const Transform kMount(0.2, 0.0, 0.3, 0.0, 0.0, 0.0);

// A differential-drive robot: constant speeds in its own frame, so it drives along a circle.
Transform robotPose(double t) {
  const double heading = kTurnRate * (t - kStamp), radius = kSpeed / kTurnRate;
  return Transform(radius * std::sin(heading), radius * (1.0 - std::cos(heading)), 0.0, 0.0, 0.0, heading);
}

// Range from (x, y) along `heading` to the square's walls.
double rangeToWalls(double x, double y, double heading) {
  const double dx = std::cos(heading), dy = std::sin(heading);
  double r = 1e9;
  if (std::abs(dx) > 1e-12) r = std::min(r, ((dx > 0 ? kHalfRoom : -kHalfRoom) - x) / dx);
  if (std::abs(dy) > 1e-12) r = std::min(r, ((dy > 0 ? kHalfRoom : -kHalfRoom) - y) / dy);
  return r;
}

sensor_msgs::LaserScan sweepingScan() {
  sensor_msgs::LaserScan scan;
  scan.header.frame_id = "laser";
  scan.header.stamp = ros::Time(kStamp);
  scan.angle_increment = static_cast<float>(2.0 * M_PI / kBeams);
  scan.angle_min = static_cast<float>(-M_PI);
  scan.angle_max = scan.angle_min + scan.angle_increment * (kBeams - 1);
  scan.time_increment = static_cast<float>(kSweep / kBeams);
  scan.scan_time = static_cast<float>(kSweep);
  scan.range_min = 0.1f;
  scan.range_max = 30.0f;
  for (int i = 0; i < kBeams; ++i) {
    const Transform laser = robotPose(kStamp + i * double(scan.time_increment)) * kMount;
    const double heading = laser.theta() + scan.angle_min + i * double(scan.angle_increment);
    scan.ranges.push_back(static_cast<float>(rangeToWalls(laser.x(), laser.y(), heading)));
    scan.intensities.push_back(float(i));
  }
  return scan;
}

// Wheel odometry at 200 Hz around the sweep, and the lidar's mounting.
void fillTf(tf2::BufferCore& buffer) {
  setTransform(buffer, "base_link", "laser", kMount, 0.0, true);
  for (double t = kStamp - 0.5; t <= kStamp + 0.5; t += 0.005) {
    setTransform(buffer, "odom", "base_link", robotPose(t), t, false);
  }
}

// Largest distance of the cloud's points (laser frame at the stamp) from the room's walls.
double worstWallError(const sensor_msgs::PointCloud2& cloud) {
  const Transform laserAtStamp = robotPose(kStamp) * kMount;
  double worst = 0.0;
  for (sensor_msgs::PointCloud2ConstIterator<float> it(cloud, "x"); it != it.end(); ++it) {
    const Eigen::Vector3d p = laserAtStamp.toEigen() * Eigen::Vector3d(it[0], it[1], it[2]);
    worst = std::max(worst, std::abs(std::max(std::abs(p.x()), std::abs(p.y())) - kHalfRoom));
  }
  return worst;
}

}  // namespace

TEST(Deskewing, ScanProjectedByLaserGeometryCarriesBeamTimes) {
  const sensor_msgs::LaserScan scan = sweepingScan();
  const sensor_msgs::PointCloud2 cloud = timedCloudFromScan(scan);
  ASSERT_EQ(cloud.width * cloud.height, uint32_t(kBeams));
  std::string error;
  const auto times = pointTimes(cloud, &error);
  ASSERT_TRUE(times) << error;
  EXPECT_NEAR(times->front(), 0.0, 1e-9);
  EXPECT_NEAR(times->back(), (kBeams - 1) * double(scan.time_increment), 1e-6);
  // The sweep really is skewed: taken as one rigid scan, walls are off by tens of centimetres.
  EXPECT_GT(worstWallError(cloud), 0.3);
}

TEST(Deskewing, WheelOdometryInTfStraightensTheWalls) {
  tf2::BufferCore buffer;
  fillTf(buffer);
  sensor_msgs::PointCloud2 cloud = timedCloudFromScan(sweepingScan());
  std::string error;
  const auto times = pointTimes(cloud, &error);
  ASSERT_TRUE(times) << error;
  const double first = *std::min_element(times->begin(), times->end());
  const double last = *std::max_element(times->begin(), times->end());
  const auto motion = SweepMotion::fromTf(buffer, "odom", "laser", cloud.header.stamp, first, last, 0.0, &error);
  ASSERT_TRUE(motion) << error;
  ASSERT_TRUE(deskewCloud(cloud, *times, *motion, &error)) << error;
  // Interpolating between the sweep's ends misses only the mount's arc (0.2 m over 0.2 rad).
  EXPECT_LT(worstWallError(cloud), 0.005);
}

TEST(Deskewing, ConstantVelocityStraightensTheWalls) {
  sensor_msgs::PointCloud2 cloud = timedCloudFromScan(sweepingScan());
  // The motion of the laser over the previous 0.1 s (what the odometry measured last), in its
  // own frame.
  const Transform laserMotion = (robotPose(kStamp - 0.1) * kMount).inverse() * (robotPose(kStamp) * kMount);
  std::string error;
  const auto times = pointTimes(cloud, &error);
  ASSERT_TRUE(times) << error;
  ASSERT_TRUE(deskewCloud(cloud, *times, SweepMotion::fromVelocity(laserMotion, 0.1), &error)) << error;
  EXPECT_LT(worstWallError(cloud), 0.005);
}

TEST(Deskewing, DeskewedScanIsPlanarWithIntensities) {
  sensor_msgs::PointCloud2 cloud = timedCloudFromScan(sweepingScan());
  const Transform laserMotion = (robotPose(kStamp - 0.1) * kMount).inverse() * (robotPose(kStamp) * kMount);
  const auto times = pointTimes(cloud);
  ASSERT_TRUE(times);
  ASSERT_TRUE(deskewCloud(cloud, *times, SweepMotion::fromVelocity(laserMotion, 0.1)));
  const auto cloudScan = laserScanFromCloudMsg(cloud, kMount);
  ASSERT_TRUE(cloudScan);
  const rtabmap::LaserScan planar = planarScan(*cloudScan);
  EXPECT_EQ(planar.format(), rtabmap::LaserScan::kXYI);
  EXPECT_EQ(planar.size(), kBeams);
  EXPECT_EQ(planar.localTransform(), kMount);
  EXPECT_FLOAT_EQ(planar.data().ptr<float>(0)[3 * 10 + 2], 10.0f);  // beam 10's intensity
}

TEST(Deskewing, MissingTfNamesTheFrames) {
  tf2::BufferCore buffer;
  setTransform(buffer, "base_link", "laser", kMount, 0.0, true);
  std::string error;
  EXPECT_FALSE(SweepMotion::fromTf(buffer, "odom", "laser", ros::Time(kStamp), 0.0, kSweep, 0.0, &error));
  EXPECT_NE(error.find("odom"), std::string::npos) << error;
}

// Lidar drivers write point times in different fields and units.
TEST(Deskewing, ReadsOusterVelodyneAndAbsoluteTimes) {
  const double epoch = 1.7e9;  // drivers that write absolute times use the wall clock
  const auto cloudWith = [epoch](const std::string& name, int datatype, double value) {
    sensor_msgs::PointCloud2 cloud;
    cloud.header.stamp = ros::Time(epoch);
    sensor_msgs::PointCloud2Modifier modifier(cloud);
    modifier.setPointCloud2Fields(4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32,
                                  "z", 1, sensor_msgs::PointField::FLOAT32, name.c_str(), 1, datatype);
    modifier.resize(1);
    uint8_t* p = cloud.data.data() + cloud.fields[3].offset;
    if (datatype == sensor_msgs::PointField::UINT32) {
      const uint32_t v = static_cast<uint32_t>(value);
      std::memcpy(p, &v, 4);
    } else if (datatype == sensor_msgs::PointField::FLOAT32) {
      const float v = static_cast<float>(value);
      std::memcpy(p, &v, 4);
    } else {
      std::memcpy(p, &value, 8);
    }
    return cloud;
  };
  const auto timeOf = [](const sensor_msgs::PointCloud2& c) {
    std::string error;
    const auto t = pointTimes(c, &error);
    EXPECT_TRUE(t) << error;
    return t ? t->front() : -1.0;
  };
  EXPECT_NEAR(timeOf(cloudWith("t", sensor_msgs::PointField::UINT32, 50e6)), 0.05, 1e-9);      // Ouster ns
  EXPECT_NEAR(timeOf(cloudWith("time", sensor_msgs::PointField::FLOAT32, 0.05)), 0.05, 1e-7);  // Velodyne s
  EXPECT_NEAR(timeOf(cloudWith("timestamp", sensor_msgs::PointField::FLOAT64, epoch + 0.05)), 0.05, 1e-6);
  std::string error;
  EXPECT_FALSE(pointTimes(cloudWith("ring", sensor_msgs::PointField::UINT32, 3), &error));
  EXPECT_NE(error.find("no per-point time field"), std::string::npos) << error;
}

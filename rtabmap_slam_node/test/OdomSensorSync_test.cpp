#include "rtabmap_slam_node/OdomSensorSync.h"

#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>

#include <cmath>

namespace rtabmap_slam_node {
namespace {

using rtabmap::Transform;

// Wheel odometry in tf: the robot drives along x at 1 m/s, turning left at 0.5 rad/s.
void drive(tf2::BufferCore& buffer) {
  for (int i = 0; i <= 40; ++i) {
    const double t = 0.05 * i;
    geometry_msgs::TransformStamped m;
    m.header.stamp = ros::Time(100.0 + t);
    m.header.frame_id = "odom";
    m.child_frame_id = "base_link";
    m.transform.translation.x = t;
    m.transform.rotation.z = std::sin(0.25 * t);  // yaw 0.5 t
    m.transform.rotation.w = std::cos(0.25 * t);
    buffer.setTransform(m, "test");
  }
}

TEST(OdomSensorSync, TheSensorTakesInTheMotionBetweenTheOdometryAndItsStamps) {
  tf2::BufferCore buffer(ros::Duration(100.0));
  drive(buffer);
  const Transform laser(0.2, 0, 0.3, 0, 0, 0);  // base_link -> laser
  std::string error;
  // The laser fired 0.5 s after the odometry's stamp: the robot had moved 0.5 m and turned
  // from 0.5 to 0.75 rad, so at the odometry's pose the laser is ahead of its mount.
  const Transform synced = odomSyncedLocalTransform(buffer, "odom", "base_link", laser, ros::Time(101.0),
                                                    ros::Time(101.5), 0.0, &error);
  ASSERT_FALSE(synced.isNull()) << error;
  const Transform odomAt1 = Transform(1.0, 0, 0, 0, 0, 0.5);
  const Transform odomAt15 = Transform(1.5, 0, 0, 0, 0, 0.75);
  // Same place in odom: odom(odom stamp) * synced == odom(sensor stamp) * laser.
  const Transform expected = odomAt1.inverse() * odomAt15 * laser;
  EXPECT_NEAR(synced.x(), expected.x(), 1e-4);
  EXPECT_NEAR(synced.y(), expected.y(), 1e-4);
  EXPECT_NEAR(synced.z(), 0.3, 1e-6);
  EXPECT_NEAR(synced.theta(), 0.25, 1e-4);
  EXPECT_GT(synced.x(), laser.x() + 0.3) << "the motion was applied backwards";
}

TEST(OdomSensorSync, SameStampsOrNoTfAnswer) {
  tf2::BufferCore buffer(ros::Duration(100.0));
  drive(buffer);
  const Transform laser(0.2, 0, 0.3, 0, 0, 0);
  const Transform same = odomSyncedLocalTransform(buffer, "odom", "base_link", laser, ros::Time(500.0),
                                                  ros::Time(500.0), 0.0);
  EXPECT_DOUBLE_EQ(same.x(), 0.2) << "equal stamps need no lookup (and tf has nothing at 500 s)";
  std::string error;
  const Transform outside = odomSyncedLocalTransform(buffer, "odom", "base_link", laser, ros::Time(101.0),
                                                     ros::Time(150.0), 0.0, &error);
  EXPECT_TRUE(outside.isNull());
  EXPECT_NE(error.find("base_link"), std::string::npos) << error;
}

}  // namespace
}  // namespace rtabmap_slam_node

#pragma once
// What the rtabmap SLAM nodelet computes around the core without ROS plumbing (unit-tested
// without a master): the occupancy grid message, the odometry covariance the core wants, the
// node's arguments and paths.
#include <Eigen/Core>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/time.h>
#include <std_msgs/Header.h>

#include <optional>
#include <string>
#include <vector>

#include "rtabmap_core/maps/GridMap.h"

namespace rtabmap_slam_node {

using Covariance6 = Eigen::Matrix<double, 6, 6>;

// The core's grid as nav_msgs/OccupancyGrid: GridMap already has the message's semantics
// (row 0 = lowest y, -1/0/100), so cells are copied row by row; origin = the corner of cell
// (0, 0), orientation identity. An empty grid gives width = height = 0 and no data.
nav_msgs::OccupancyGrid gridMapToMsg(const rtabmap::GridMap& grid, const std_msgs::Header& header);

// The core links a new node to the previous one with the covariance of the motion between
// them. Odometry topics publish one of two things, and nothing in nav_msgs/Odometry says which,
// so the odom_covariance_cumulative parameter does:
//  - false (rtabmap's own odometry): the message's covariance is already the motion's since
//    the previous odometry frame; it is used as is;
//  - true (wheel odometry integrating from the start: the covariance only grows): the motion's
//    covariance is the difference with the previous processed message's.
// Either way each variance is floored at minVariance (a zero variance would be an infinite
// information), and an axis the odometry does not observe (variance >= kUnobservedVariance,
// e.g. z, roll, pitch of planar wheel odometry) keeps the message's variance, not a difference.
constexpr double kUnobservedVariance = 1e3;
Covariance6 motionCovariance(const Covariance6& current, const Covariance6* previous, bool cumulative,
                             double minVariance = 1e-9);

// Odometry from tf (no covariance there): the classic odom_tf_linear_variance (x, y, z) and
// odom_tf_angular_variance (roll, pitch, yaw) on the diagonal.
Covariance6 tfOdometryCovariance(double linearVariance, double angularVariance);

// The nodelet's arguments (launch-prefix args="-d" or nodelet load ... -- -d).
struct NodeArguments {
  bool deleteDbOnStart = false;        // -d, --delete_db_on_start
  std::vector<std::string> unknown;    // anything else (warned)
};
NodeArguments parseNodeArguments(const std::vector<std::string>& argv);

// "~/x" -> "$HOME/x" (ROS params are not shell-expanded); other paths unchanged.
std::string expandHome(const std::string& path);

// Stamps of map -> odom, sent on a wall timer at now + tf_tolerance. A stopped simulated clock
// (a bag paused or over) repeats that stamp, and tf listeners drop data at a stamp they already
// hold (warning each time): nothing is sent then, unless the correction changed since the last
// one sent (the node still catching up with queued data after the bag ended), which goes out one
// nanosecond after it, so that listeners take it as the newest.
class MapToOdomStamps {
 public:
  // The stamp to send the current correction with, or nothing to send. `wanted` = now +
  // tf_tolerance; `correctionChanged`: differs from the last correction sent.
  std::optional<ros::Time> next(const ros::Time& wanted, bool correctionChanged);

 private:
  ros::Time lastWanted_, lastSent_;
};

}  // namespace rtabmap_slam_node

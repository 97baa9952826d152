#pragma once
// What the odometry nodes compute around the core's odometry, without ROS plumbing
// (unit-tested): the tf correction published with a wheel-odometry guess, the clouds of
// odom_local_map / odom_last_frame, and the update rate limits.
#include <Eigen/Core>
#include <opencv2/core/types.hpp>

#include <vector>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_odom {

// With guess_frame_id (wheel odometry, e.g. "odom_wheel" -> base_link already in tf), the base
// frame has a parent, so the node cannot publish odom -> base_link itself. It publishes the
// correction odom -> guess frame instead: the pose of the guess frame in odom, such that
// odom -> guess -> base equals the odometry pose. odomPose: base in odom; guessPose: base in
// the guess frame, both at the frame's stamp.
rtabmap::Transform guessFrameCorrection(const rtabmap::Transform& odomPose, const rtabmap::Transform& guessPose);

// The twist (vx vy vz wx wy wz, in the base frame) of a motion found over dt seconds: what
// nav_msgs/Odometry's twist carries for filters that fuse velocities (robot_localization).
// Zero when the motion is null or dt <= 0.
Eigen::Matrix<double, 6, 1> twistFromMotion(const rtabmap::Transform& motion, double dt);

// Finite 3D points as an XYZ scan (identity local transform): visual features (NaN where no
// depth) for display.
rtabmap::LaserScan pointsAsScan(const std::vector<cv::Point3f>& points);

// The scan's points in the frame where its base frame has pose `pose` (e.g. the odometry
// frame): sensor -> base (local transform) -> pose. Same format; identity local transform.
rtabmap::LaserScan scanInFrame(const rtabmap::LaserScan& scan, const rtabmap::Transform& pose);

// max_update_rate: process a frame only when its stamp is at least 1 / rate after the last
// processed one (data stamps, so a bag played faster keeps the same frames). A stamp before
// the last one (bag restarted, reset) starts over. rate <= 0: every frame.
class UpdateRateLimiter {
 public:
  explicit UpdateRateLimiter(double rate = 0.0) : rate_(rate) {}
  bool accept(double stamp);
  void reset() { last_ = -1.0; }

 private:
  double rate_;
  double last_ = -1.0;
};

// expected_update_rate: true when fewer updates than 80 % of the expected rate came in over
// the window (tolerates the jitter of a live sensor, catches a node falling behind).
bool updateRateTooLow(int updates, double windowSeconds, double expectedRate);

}  // namespace rtabmap_odom

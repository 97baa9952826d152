#pragma once
// The `imu` topic of the rtabmap and odometry nodes: the orientations an IMU filter publishes
// (sensor_msgs/Imu with an orientation, e.g. imu_filter_madgwick's output, at 100-400 Hz), kept
// for a few seconds so each frame gets the orientation at its own stamp. The core turns it into
// the node's gravity link (rtabmap_core/memory/GravityLink.h; used with Optimizer/GravitySigma >
// 0) and odometry into a levelled start and the rotation of its motion guess
// (rtabmap_core/odometry/Odometry.h). Thread-safe: the imu callback and the data callback may
// run at once.
#include <Eigen/Geometry>

#include <chrono>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include <sensor_msgs/Imu.h>

#include "rtabmap_core/geometry/IMU.h"

namespace rtabmap_conversions {

struct ImuOrientation {
  double stamp = 0.0;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // of frameId in the IMU's world
  std::string frameId;
};

class ImuOrientationBuffer {
 public:
  // keepSeconds: history kept behind the newest sample. maxGapSeconds: two samples farther
  // apart than this do not interpolate (the IMU stopped), and a stamp at most this far past
  // the newest sample takes it as it is.
  explicit ImuOrientationBuffer(double keepSeconds = 5.0, double maxGapSeconds = 0.1);

  // False, with why, for a sample that cannot be used: not finite, a null quaternion, or not
  // newer than the previous one (out of order). A sample older than the whole history kept
  // means ROS time went back: the history is dropped and the sample taken.
  bool add(const ImuOrientation& sample, std::string* why = nullptr);
  // The orientation at `stamp`: spherical interpolation between the samples around it; none
  // when no sample is within maxGapSeconds (the caller then gives the frame no orientation).
  std::optional<ImuOrientation> at(double stamp) const;

  enum class Intake { kKept, kNoOrientation, kRefused };
  // A message of the topic: kept, without an orientation (a raw IMU: nothing to keep), or
  // refused (not finite, out of order; why says it). `converted` (optional) receives the message
  // as a core IMU unless it is refused, for a caller that uses its angular velocity too.
  Intake add(const sensor_msgs::Imu& msg, std::string* why = nullptr, rtabmap::IMU* converted = nullptr);
  // The IMU frame's pose on the robot: localOf(frameId, why)'s (a tf lookup; null when unknown),
  // kept once found (a mounting does not move). After a failure localOf is asked again at most
  // once a second: each lookup may wait for tf, and samples come at hundreds of Hz.
  using LocalPoseOf = std::function<rtabmap::Transform(const std::string& frameId, std::string* why)>;
  rtabmap::Transform mountOf(const std::string& frameId, const LocalPoseOf& localOf, std::string* why = nullptr) const;
  // The IMU a frame at `stamp` carries: the orientation there with its frame's mountOf(). None,
  // with why, when either is missing.
  std::optional<rtabmap::IMU> imuAt(double stamp, const LocalPoseOf& localOf, std::string* why = nullptr) const;
  bool empty() const;
  void clear();  // ROS time jumped back (a restarted bag): older stamps come again

 private:
  double keep_, maxGap_;
  mutable std::mutex mutex_;
  std::deque<ImuOrientation> samples_;  // by increasing stamp
  mutable std::mutex mountMutex_;  // not held while localOf looks tf up
  mutable std::map<std::string, rtabmap::Transform> mounts_;
  mutable std::map<std::string, std::chrono::steady_clock::time_point> mountFailures_;  // the last one
};

}  // namespace rtabmap_conversions

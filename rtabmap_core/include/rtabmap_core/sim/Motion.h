#pragma once
// Robot motion: a planned reference path through waypoints, and a differential-drive robot
// that tracks it.
//
// ReferencePath turns a polyline of waypoints (through corridors and doorways) into a smooth,
// time-parametrised plan: corners up to `pivotAngle` are rounded with circular arcs (radius up
// to cornerRadius, smaller where the segments are short); sharper ones (dead ends, turning back
// in a room) stop and turn in place. The speed profile respects the top speed, the yaw-rate and
// lateral-acceleration limits on arcs, and the acceleration limit (forward-backward pass); the
// robot rests `dwell` seconds at the start and at the end (an IMU sees gravity alone there).
//
// RobotSimulator is the "real" robot: a unicycle whose speed and yaw rate change only within
// acceleration limits, driven by a trajectory-tracking controller (feedforward of the plan plus
// feedback on the pose error, Kanayama-style). Its state at every 1 ms step is the ground truth;
// the limits make the yaw rate continuous, as a real robot's is.
#include <Eigen/Core>

#include <vector>

#include "rtabmap_core/sim/Pose2.h"

namespace rtabmap::sim {

struct MotionLimits {
  double maxSpeed = 0.5;         // m/s, planned cruise speed (indoor robots: 0.3-0.7)
  double maxAcceleration = 0.4;  // m/s^2, planned
  double maxYawRate = 0.8;       // rad/s, planned
  double maxYawAcceleration = 1.5;  // rad/s^2, planned (in-place turns)
  double maxLateralAcceleration = 0.35;  // m/s^2 on arcs
  double cornerRadius = 0.5;     // m, largest arc at a corner
  double pivotAngle = 100.0 * M_PI / 180.0;  // sharper corners turn in place
  double dwell = 1.0;            // s at rest at the start and the end
  // The robot's own limits (a little above the plan's, so it can catch up).
  double robotAcceleration = 1.0;     // m/s^2
  double robotYawAcceleration = 3.0;  // rad/s^2
};

// The plan's state at a time.
struct ReferenceState {
  double x = 0.0, y = 0.0, yaw = 0.0;  // yaw unwrapped (continuous along the path)
  double v = 0.0;      // m/s
  double omega = 0.0;  // rad/s
};

class ReferencePath {
 public:
  // Needs at least two distinct waypoints (std::invalid_argument otherwise).
  ReferencePath(const std::vector<Eigen::Vector2d>& waypoints, const MotionLimits& limits);

  double duration() const { return duration_; }
  double length() const { return length_; }
  ReferenceState at(double t) const;
  const MotionLimits& limits() const { return limits_; }
  double initialYaw() const { return samples_.front().yaw; }

 private:
  struct Sample {
    double t;
    double x, y, yaw;  // yaw unwrapped
    double kappa;      // curvature (translation) or 0
    double v;          // m/s (translation samples)
    double omega;      // rad/s (in-place turn samples)
  };
  void appendTranslation(const std::vector<Sample>& geometry);
  void appendTurn(double x, double y, double yaw0, double angle);
  void appendRest(double seconds);
  // Length of `segment` (between waypoints segment and segment + 1) a corner at one of its ends
  // may round off.
  double cornerRoom(size_t segment, const std::vector<double>& turn, const std::vector<bool>& pivot,
                    const std::vector<double>& lens) const;

  MotionLimits limits_;
  std::vector<Sample> samples_;  // time-ordered; interpolated linearly between
  double duration_ = 0.0;
  double length_ = 0.0;
};

// The robot's true state.
struct RobotState {
  double t = 0.0;  // seconds since the start
  Pose2 pose;
  double v = 0.0;      // forward speed, m/s
  double omega = 0.0;  // yaw rate, rad/s
  double acceleration = 0.0;  // dv/dt over the last step, m/s^2
};

class RobotSimulator {
 public:
  // Starts at rest on the path's first pose.
  RobotSimulator(const ReferencePath& path, double step = 0.001);
  // Advances one step (speed and yaw rate constant during it; the pose integrates them exactly).
  const RobotState& step();
  const RobotState& state() const { return state_; }
  double stepSeconds() const { return dt_; }
  // True once the plan is over (the robot has stopped at its end).
  bool finished() const { return state_.t >= path_.duration(); }

 private:
  const ReferencePath& path_;
  double dt_;
  RobotState state_;
  double yawUnwrapped_;
  long long steps_ = 0;  // time = steps * step, without summing rounding errors
};

}  // namespace rtabmap::sim

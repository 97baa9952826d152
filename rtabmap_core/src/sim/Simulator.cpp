#include "rtabmap_core/sim/Simulator.h"

#include <opencv2/imgproc.hpp>

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace rtabmap::sim {

ViewPose viewFrom(const Pose2& base, const Transform& baseToOptical) {
  const Transform optical = base.toTransform() * baseToOptical;
  const Eigen::Vector3d axis = optical.rotationMatrix().col(2);  // the optical z axis
  ViewPose v;
  v.x = optical.x();
  v.y = optical.y();
  v.z = optical.z();
  v.yaw = std::atan2(axis.y(), axis.x());
  return v;
}

Simulator::Simulator(const World& world, const SimulationConfig& config)
    : world_(world), config_(config), renderer_(world, config.camera.intrinsics, config.render) {
  auto check = [&](double rate, const char* what) {
    if (!(rate > 0.0) || rate * config.step > 1.0 + 1e-9) {
      throw std::invalid_argument(std::string("Simulator: ") + what + " must be > 0 and at most " +
                                  std::to_string(1.0 / config.step) + " Hz");
    }
  };
  if (!(config.step > 0.0)) throw std::invalid_argument("Simulator: step must be > 0");
  check(config.frameRate, "frame rate");
  check(config.imuRate, "IMU rate");
  check(config.odomRate, "odometry rate");
}

SimFrame Simulator::capture(const Pose2& base, int index, double stamp, uint64_t noiseKey) const {
  SimFrame f;
  f.index = index;
  f.stamp = stamp;
  f.groundTruth = base;
  if (config_.colour || config_.stereo) {
    renderer_.render(viewFrom(base, config_.camera.baseToOptical), f.bgr, &f.depth, hashCombine(noiseKey, 1));
  }
  if (config_.stereo) {
    cv::Mat rightColour;
    renderer_.render(viewFrom(base, config_.camera.baseToRightOptical()), rightColour, nullptr, hashCombine(noiseKey, 2));
    cv::cvtColor(rightColour, f.right, cv::COLOR_BGR2GRAY);
  }
  if (config_.scanUrg) f.urg = simulateLaser(world_, config_.urg, base, hashCombine(noiseKey, 3));
  if (config_.scanUtm) f.utm = simulateLaser(world_, config_.utm, base, hashCombine(noiseKey, 4));
  if (config_.lidar3d) f.lidar = simulateLidar(world_, config_.lidar, base, hashCombine(noiseKey, 5));
  return f;
}

SessionSummary Simulator::run(const ReferencePath& path, SimulationSink& sink, uint64_t seed,
                              const std::function<void(double)>& progress) const {
  const SimulationConfig& c = config_;
  const long long perSecond = std::llround(1.0 / c.step);
  const long long imuEvery = std::max(1LL, std::llround(perSecond / c.imuRate));
  const long long odomEvery = std::max(1LL, std::llround(perSecond / c.odomRate));
  const double duration = c.maxDuration > 0.0 ? std::min(c.maxDuration, path.duration()) : path.duration();
  const long long lastTick = std::llround(duration * perSecond);
  RobotSimulator robot(path, c.step);
  WheelOdometry odometry(c.odometryNoise, seed, 2);
  ImuModel imu(c.imuNoise, c.imuRate, seed);
  odometry.reset(robot.state().pose);

  SessionSummary summary;
  summary.start = robot.state().pose;
  int frameIndex = 0;
  long long nextFrame = 0;
  auto stampAt = [&](long long tick) { return c.startStamp + static_cast<double>(tick) * c.step; };
  for (long long tick = 0; tick <= lastTick; ++tick) {
    if (tick > 0) {
      const RobotState& s = robot.step();
      imu.accumulate(c.step, s.v, s.omega, s.acceleration);
      odometry.update(s.pose);
      summary.distance += std::fabs(s.v) * c.step;
    }
    const double stamp = stampAt(tick);
    if (tick > 0 && tick % imuEvery == 0) {
      sink.onImu(imu.sample(stamp));
      ++summary.imuSamples;
    }
    if (tick % odomEvery == 0) {
      const OdometryIncrement inc = odometry.take(1);
      OdometrySample o;
      o.stamp = stamp;
      o.pose = odometry.pose();
      o.covariance = inc.covariance;
      const double period = tick > 0 ? static_cast<double>(odomEvery) * c.step : 1.0;
      o.v = tick > 0 ? std::hypot(inc.motion.x, inc.motion.y) * (inc.motion.x >= 0 ? 1.0 : -1.0) / period : 0.0;
      o.omega = tick > 0 ? inc.motion.yaw / period : 0.0;
      sink.onOdometry(o);
      ++summary.odometrySamples;
    }
    if (tick == nextFrame) {
      const auto t0 = std::chrono::steady_clock::now();
      SimFrame frame = capture(robot.state().pose, frameIndex, stamp, hashCombine(seed, static_cast<uint64_t>(frameIndex)));
      summary.renderSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const OdometryIncrement inc = odometry.take(0);
      frame.odometry = odometry.pose();
      frame.odometryCovariance = inc.covariance;
      sink.onFrame(std::move(frame));
      ++frameIndex;
      nextFrame = std::llround(static_cast<double>(frameIndex) * static_cast<double>(perSecond) / c.frameRate);
      if (progress) progress(lastTick > 0 ? static_cast<double>(tick) / static_cast<double>(lastTick) : 1.0);
    }
  }
  summary.frames = frameIndex;
  summary.duration = static_cast<double>(lastTick) * c.step;
  summary.end = robot.state().pose;
  return summary;
}

}  // namespace rtabmap::sim

#pragma once
// The simulation loop: drives the robot along a planned path in 1 ms steps and streams what
// its sensors produce, in time order, to a sink (the dataset writer, a test, a benchmark).
//
// Clock: integer steps from `startStamp`. IMU samples every 1/imuRate, wheel odometry every
// 1/odomRate, frames (camera images and the scans taken with them) every 1/frameRate, each at
// the step nearest its ideal time. At equal stamps the order is IMU, odometry, frame, so a
// consumer has the motion up to a frame before the frame.
#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include <cstdint>
#include <functional>

#include "rtabmap_core/sim/ImuModel.h"
#include "rtabmap_core/sim/Motion.h"
#include "rtabmap_core/sim/RangeSensors.h"
#include "rtabmap_core/sim/Renderer.h"
#include "rtabmap_core/sim/SensorRig.h"
#include "rtabmap_core/sim/WheelOdometry.h"
#include "rtabmap_core/sim/World.h"

namespace rtabmap::sim {

struct SimulationConfig {
  CameraSpec camera = CameraSpec::standard();
  LaserSpec urg = LaserSpec::urg04lx();
  LaserSpec utm = LaserSpec::utm30lx();
  LidarSpec lidar = LidarSpec::vlp16();
  bool colour = true;      // RGB + registered depth
  bool stereo = true;      // the right image of the stereo pair (the left is the RGB image)
  bool scanUrg = true;
  bool scanUtm = true;
  bool lidar3d = false;
  double frameRate = 10.0;   // Hz
  double imuRate = 200.0;    // Hz
  double odomRate = 50.0;    // Hz
  double step = 0.001;       // s, simulation step
  RenderOptions render;
  OdometryNoise odometryNoise;
  ImuNoise imuNoise;
  MotionLimits motion;
  double maxDuration = 0.0;  // s, stop early (0: the whole path)
  double startStamp = 1700000000.0;  // s, stamp of the first step (2023-11-14)
};

// Everything sensed at one frame time.
struct SimFrame {
  int index = 0;
  double stamp = 0.0;
  Pose2 groundTruth;  // base in the world frame
  Pose2 odometry;     // base in the odometry frame (identity where the session started)
  Eigen::Matrix3d odometryCovariance = Eigen::Matrix3d::Zero();  // motion since the previous frame (x, y, yaw)
  cv::Mat bgr;        // CV_8UC3
  cv::Mat depth;      // CV_32FC1, metres along the optical axis
  cv::Mat right;      // CV_8UC1, right camera of the stereo pair
  LaserReading urg;
  LaserReading utm;
  cv::Mat lidar;      // 1 x N CV_32FC4 in the lidar frame
};

struct OdometrySample {
  double stamp = 0.0;
  Pose2 pose;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // motion since the previous sample
  double v = 0.0;      // measured forward speed over the last period, m/s
  double omega = 0.0;  // measured yaw rate, rad/s
};

class SimulationSink {
 public:
  virtual ~SimulationSink() = default;
  virtual void onImu(const ImuSample&) {}
  virtual void onOdometry(const OdometrySample&) {}
  virtual void onFrame(SimFrame&& frame) = 0;
};

struct SessionSummary {
  int frames = 0;
  int imuSamples = 0;
  int odometrySamples = 0;
  double duration = 0.0;      // s
  double distance = 0.0;      // m driven
  double renderSeconds = 0.0; // wall time spent capturing frames
  Pose2 start;                // ground truth at the start and end
  Pose2 end;
};

class Simulator {
 public:
  // Throws std::invalid_argument for rates that are not positive or finer than the step.
  Simulator(const World& world, const SimulationConfig& config);
  const SimulationConfig& config() const { return config_; }
  const World& world() const { return world_; }

  // Every enabled sensor at a base pose (no motion, no odometry): for tests and benchmarks.
  SimFrame capture(const Pose2& base, int index = 0, double stamp = 0.0, uint64_t noiseKey = 0) const;
  // Drives the path, streaming samples to the sink. `seed` seeds the odometry, IMU and sensor
  // noise; `progress` (if set) gets the fraction done after each frame.
  SessionSummary run(const ReferencePath& path, SimulationSink& sink, uint64_t seed,
                     const std::function<void(double)>& progress = {}) const;

 private:
  const World& world_;
  SimulationConfig config_;
  Renderer renderer_;
};

// Where a camera mounted at baseToOptical looks from, for a robot at `base`.
ViewPose viewFrom(const Pose2& base, const Transform& baseToOptical);

}  // namespace rtabmap::sim

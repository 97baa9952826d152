#pragma once
// The "sim" dataset folder: what rtabmap-sim writes and the "sim" DatasetReader reads.
//
//   DIR/
//     info.yaml          what was simulated and how: format (rtabmap_sim_dataset) and its
//                        version, simulator version, scenario, session, seed, every option,
//                        counts (frames, IMU and odometry samples), duration, distance, and the
//                        sensors present with their parameters (see below)
//     calib/rgb.yaml     ROS camera_info YAML of the RGB camera (CameraModel::save), with its
//                        local transform base_link -> optical frame; the RGB camera is also the
//     calib/left.yaml    left camera of the rectified stereo pair (same intrinsics, named left)
//     calib/right.yaml   right camera: P(0,3) = Tx = -fx * baseline, its own local transform
//     transforms.txt     static transforms, one per line: `parent child x y z qx qy qz qw`
//                        (base_link -> camera_rgb_optical_frame, camera_right_optical_frame,
//                        laser_urg, laser_utm, lidar, imu_link)
//     frames.txt         one line per frame: `index stamp x y z qx qy qz qw cxx cxy cxw cyy cyw cww`
//                        - the wheel-odometry pose of the base at the frame and the covariance of
//                        the odometry motion since the previous frame (x, y, yaw: upper triangle)
//     groundtruth.txt    TUM `stamp x y z qx qy qz qw`: the true base_link pose in the world
//                        frame at each frame (rtabmap-eval ate reads it directly)
//     odometry.txt       TUM: the wheel-odometry pose at the odometry rate (odometry frame:
//                        identity where the run started)
//     odometry_twist.txt one line per odometry.txt line: `stamp v w cxx cxy cxw cyy cyw cww`:
//                        measured speed (m/s), yaw rate (rad/s) and the covariance of the motion
//                        since the previous odometry sample
//     imu.txt            `stamp wx wy wz ax ay az`: gyro (rad/s) and specific force (m/s^2, +g
//                        up at rest) in imu_link, at the IMU rate
//     rgb/NNNNNN.png     colour, 8-bit BGR (lossless PNG)          \  NNNNNN: the frame index,
//     depth/NNNNNN.png   depth registered to rgb, 16-bit mm (0 =   |  6 digits from 000000
//                        nothing; PNG)                             |
//     depth32/NNNNNN.bin optional (--depth32): exact float depth,   |
//                        metres, as codec::compressData (zlib)     |
//     right/NNNNNN.png   right stereo image, 8-bit grey (the left  |
//                        image is the RGB image in grey: BGR2GRAY) |
//     scan_urg/NNNNNN.bin  planar scans: little-endian float32     |
//     scan_utm/NNNNNN.bin  ranges[beams] then intensities[beams]   |
//                        (+inf: no return, REP-117)                |
//     lidar/NNNNNN.bin   3D points, little-endian float32 x y z    /
//                        intensity per point, in the lidar frame (KITTI velodyne layout)
//
// A folder holds the sensors that were enabled (info.yaml says which). Stamps are seconds
// (printed with 6 decimals) of the simulation clock, which starts at --start-stamp.
// A multi-session scenario writes DIR/info.yaml (the scenario and its sessions) and one such
// folder per session: DIR/session1, DIR/session2, ...
//
// Everything written is a function of the scenario, seed and options: the same command gives
// byte-identical files (nothing about the machine, the time of day or the output path is
// written).
#include <Eigen/Core>

#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "rtabmap_core/sim/Simulator.h"

namespace rtabmap::sim {

constexpr const char* kSimulatorVersion = "1.0.0";
constexpr const char* kSimDatasetFormat = "rtabmap_sim_dataset";
constexpr int kSimDatasetFormatVersion = 1;

// What info.yaml records besides the configuration: the run's identity and its options as the
// user gave them (name, value), in order.
struct SimDatasetInfo {
  std::string scenario;
  std::string session;  // "" for single-session scenarios
  uint64_t seed = 0;
  std::vector<std::pair<std::string, std::string>> options;
};

// Path of frame `index`'s file in a sensor folder: "rgb/000042.png".
std::string simFramePath(const std::string& folder, int index, const std::string& extension);

class SimDatasetWriter : public SimulationSink {
 public:
  // Creates the folder (and parents) and its sensor subfolders; throws rtabmap::Error if it
  // cannot. Files of the same names are replaced (clearing a previous run is the caller's
  // choice: rtabmap-sim --overwrite). `threads` encode images in parallel (>= 1).
  SimDatasetWriter(const std::string& dir, const SimulationConfig& config, const SimDatasetInfo& info,
                   int threads = 1, bool writeDepth32 = false);
  ~SimDatasetWriter() override;
  SimDatasetWriter(const SimDatasetWriter&) = delete;
  SimDatasetWriter& operator=(const SimDatasetWriter&) = delete;

  void onImu(const ImuSample& sample) override;
  void onOdometry(const OdometrySample& sample) override;
  void onFrame(SimFrame&& frame) override;
  // Waits for the image encoders and writes info.yaml. Throws rtabmap::Error if a file could
  // not be written.
  void finish(const SessionSummary& summary);
  const std::string& dir() const { return dir_; }

 private:
  void enqueue(std::function<void()> job);
  void worker();
  void writeStatic();

  std::string dir_;
  SimulationConfig config_;
  SimDatasetInfo info_;
  bool depth32_;
  std::FILE* frames_ = nullptr;
  std::FILE* groundTruth_ = nullptr;
  std::FILE* odometry_ = nullptr;
  std::FILE* twist_ = nullptr;
  std::FILE* imu_ = nullptr;
  bool finished_ = false;

  std::mutex mutex_;
  std::condition_variable jobReady_;
  std::condition_variable jobDone_;
  std::deque<std::function<void()>> jobs_;
  size_t running_ = 0;
  bool stopping_ = false;
  std::string firstError_;
  std::vector<std::thread> threads_;
};

// Writes the top-level info.yaml of a multi-session scenario (the sessions are subfolders).
void writeSimScenarioInfo(const std::string& dir, const SimDatasetInfo& info, const std::vector<std::string>& sessions);

}  // namespace rtabmap::sim

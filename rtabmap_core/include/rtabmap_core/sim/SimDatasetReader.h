#pragma once
// Reader of the "sim" dataset folders written by rtabmap-sim (layout: SimDatasetWriter.h), as a
// DatasetReader (format "sim", registered with openDatasetReader) and with direct access to
// every file of a frame.
//
// The stream, in time order (at equal stamps: kImu, then kOdometry, then kFrame):
//   kFrame     SensorData with id = index + 1, the camera images (see Camera below), one scan
//              (see Scan below), the wheel-odometry pose and the 6x6 covariance of the odometry
//              motion since the previous frame, and the ground truth (base_link in the world)
//   kImu       IMU samples (imu.txt), with covariances from the noise model and the local
//              transform base_link -> imu_link (if DatasetReaderOptions::imu)
//   kOdometry  wheel-odometry samples (odometry.txt, at their own rate, usually above the frame
//              rate) with the covariance of the motion since the previous sample (if
//              DatasetReaderOptions::odometry)
// The 6x6 covariances (x y z roll pitch yaw) hold the planar x, y, yaw block as written, and
// 1e-6 for z, roll and pitch (the robot is planar: its odometry has none of them); diagonal
// entries are at least 1e-9, so noise-free odometry still gives an invertible matrix.
//
// Window (startFrame, maxFrames), as the other readers of the project: IMU and odometry
// records after the last skipped frame are kept; the stream ends with the last kept frame.
//
// Which camera images and which scan a frame carries (a SensorData holds one of each):
//   camera  rgbd (RGB + registered depth, 16UC1 mm; 32FC1 m with depth32 when depth32/ was
//           written), stereo (left = the RGB image in grey, right grey, StereoCameraModel), or
//           none
//   scan    urg (URG-04LX, XYI), utm (UTM-30LX, XYI), lidar (XYZI point cloud), or none
// By default, what info.yaml's reader_defaults says (rgbd and urg when present). Through
// openDatasetReader("sim", path) the choice can ride on the path as a query:
//   DIR?camera=stereo&scan=utm&depth32=1
#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/StereoCameraModel.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap::sim {

struct SimReaderOptions {
  enum class Camera { kDefault, kRgbd, kStereo, kNone };
  enum class Scan { kDefault, kUrg, kUtm, kLidar, kNone };
  Camera camera = Camera::kDefault;
  Scan scan = Scan::kDefault;
  bool depth32 = false;  // float depth (needs depth32/ in the folder)
};

// Splits "DIR?camera=stereo&scan=utm&depth32=1" into the folder and options. Throws
// FormatError for an unknown key or value.
std::string parseSimReaderQuery(const std::string& pathWithQuery, SimReaderOptions& options);

// Everything stored for one frame (what was written and asked for; empty otherwise).
struct SimFrameRecord {
  int index = 0;
  double stamp = 0.0;
  Transform odometry;
  Eigen::Matrix<double, 6, 6> odometryCovariance = Eigen::Matrix<double, 6, 6>::Identity();
  Transform groundTruth;
  cv::Mat rgb;      // CV_8UC3
  cv::Mat depth;    // CV_16UC1 mm
  cv::Mat depth32;  // CV_32FC1 m (if written)
  cv::Mat right;    // CV_8UC1
  LaserScan urg;    // XYI in laser_urg
  LaserScan utm;    // XYI in laser_utm
  LaserScan lidar;  // XYZI in lidar
};

// What info.yaml says about the run.
struct SimDatasetMeta {
  std::string simulatorVersion;
  std::string scenario;
  std::string session;
  unsigned long long seed = 0;
  int frames = 0;
  double duration = 0.0;
  double distance = 0.0;
  bool rgb = false, depth32 = false, stereo = false, urg = false, utm = false, lidar = false;
  double imuGyroVariance = 0.0;
  double imuAccelVariance = 0.0;
  std::map<std::string, std::string> options;
};

class SimDatasetReader : public DatasetReader {
 public:
  // Throws FormatError if `dir` is not a sim dataset folder (with what was expected), or names
  // the session folders when it holds a multi-session scenario.
  SimDatasetReader(const std::string& dir, const DatasetReaderOptions& options = {},
                   const SimReaderOptions& simOptions = {});
  ~SimDatasetReader() override;

  std::string format() const override { return "sim"; }
  bool next(DatasetRecord& record) override;
  int frameCount() const override;

  // ---- direct access ----
  const SimDatasetMeta& meta() const { return meta_; }
  int totalFrames() const { return static_cast<int>(frames_.size()); }
  // All files of frame `index` (0-based, whatever the window). Throws FormatError on a missing
  // or corrupt file, std::out_of_range on a bad index.
  SimFrameRecord readFrame(int index, bool images = true, bool scans = true) const;
  const CameraModel& rgbModel() const { return rgbModel_; }
  const StereoCameraModel& stereoModel() const { return stereoModel_; }
  // Static transforms base_link -> child frame (camera_rgb_optical_frame, laser_urg, ...).
  const std::map<std::string, Transform>& staticTransforms() const { return transforms_; }
  SimReaderOptions::Camera camera() const { return camera_; }
  SimReaderOptions::Scan scan() const { return scan_; }

 private:
  struct FrameRow {
    int index;
    double stamp;
    Transform odometry;
    Eigen::Matrix<double, 6, 6> covariance;
    Transform groundTruth;
  };
  // A text table read line by line (imu.txt, odometry.txt + odometry_twist.txt).
  class LineSource;

  void readInfo();
  void readTables();
  LaserScan readScan(const std::string& folder, int index, const std::string& which) const;
  bool peekAux(DatasetRecord& record, int& kind);  // the earlier of the next IMU / odometry record

  std::string dir_;
  DatasetReaderOptions options_;
  SimReaderOptions simOptions_;
  SimDatasetMeta meta_;
  SimReaderOptions::Camera camera_ = SimReaderOptions::Camera::kNone;
  SimReaderOptions::Scan scan_ = SimReaderOptions::Scan::kNone;
  CameraModel rgbModel_;
  StereoCameraModel stereoModel_;
  std::map<std::string, Transform> transforms_;
  std::map<std::string, std::map<std::string, double>> laserSpecs_;  // scan_urg / scan_utm / lidar fields
  std::vector<FrameRow> frames_;

  // Stream state.
  std::unique_ptr<LineSource> imu_;
  std::unique_ptr<LineSource> odometry_;
  std::unique_ptr<LineSource> twist_;
  bool haveImu_ = false, haveOdometry_ = false;
  DatasetRecord nextImu_, nextOdometry_;
  int nextFrame_ = 0;   // index into frames_
  int lastFrame_ = 0;   // one past the last frame of the window
  double skipUntil_ = -1e300;  // aux records at or before this stamp are dropped
};

// The factory registered as "sim" (accepts the DIR?query form).
std::unique_ptr<DatasetReader> openSimDataset(const std::string& path, const DatasetReaderOptions& options);

}  // namespace rtabmap::sim

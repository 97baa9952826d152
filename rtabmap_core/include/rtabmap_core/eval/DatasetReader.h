#pragma once
// Datasets as a time-ordered stream of records. Every offline tool (odometry and SLAM over a
// dataset, rosbag conversion, evaluation) reads data through this one interface, whatever the
// layout on disk: CARMEN logs, 7-Scenes / TUM RGB-D folders, EuRoC ASL, KITTI odometry, image
// folders, and the simulator's own folders.
//
// Conventions of the readers of this area (each reader's .cpp documents its layout):
//  - Stamps are the dataset's own clock in seconds; layouts without times synthesise them at a
//    fixed rate (7-Scenes 30 Hz, image folders 1 Hz, KITTI without times.txt 10 Hz; see
//    DatasetReaderOptions::frameRate). Records come in time order.
//  - Frame ids (data.id()) are 1-based positions in the whole dataset (frame N of a numbered
//    layout has id N + 1), whatever startFrame is.
//  - Ground truth (data.groundTruth()) is the pose of the *base* frame, the frame the sensors'
//    local transforms start from, so it compares directly with a SLAM trajectory of the base.
//    Hand-held cameras (7-Scenes, TUM) and KITTI put the base at the camera with ROS body axes
//    (x forward, y left, z up) and CameraModel::opticalRotation() as camera local transform;
//    EuRoC's base is its body (IMU) frame. The world frame is the dataset's own, except KITTI's,
//    whose world is an optical frame and is re-expressed with ROS axes (the base at frame 0).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/SensorData.h"

namespace rtabmap {

// One element of a dataset stream.
struct DatasetRecord {
  enum class Kind {
    kFrame,     // a sensor frame: images and/or scan, with the odometry and ground truth of
                // that instant when the dataset has them (data.odomPose(), data.groundTruth())
    kImu,       // an IMU sample only (data.imu()), at the IMU rate
    kOdometry,  // a wheel-odometry sample only (data.odomPose(), covariance), at its own rate
  };
  Kind kind = Kind::kFrame;
  double stamp = 0.0;  // seconds, the dataset's own clock; equals data.stamp()
  SensorData data;
};

// Options common to every reader.
struct DatasetReaderOptions {
  int startFrame = 0;        // skip the frames before this index
  int maxFrames = 0;         // stop after this many frames (0 = all)
  bool imu = true;           // emit kImu records when the dataset has an IMU
  bool odometry = true;      // emit kOdometry records when the dataset has wheel odometry
  bool images = true;        // load images (false: scans/poses only, much faster)
  bool scans = true;         // load laser scans / point clouds
  std::string groundTruthPath;  // override the dataset's ground-truth file (e.g. EuRoC TUM gt)
  // Added (eval owner):
  // Frame rate (Hz) used to synthesise stamps for layouts without times: "7scenes" (default
  // 30 Hz), "images" (default 1 Hz), "kitti" without times.txt (default 10 Hz). 0 = default.
  double frameRate = 0.0;
  // Camera calibration overriding the layout's own: a ROS camera_info YAML for "tum", "7scenes"
  // (the colour camera's) and "images"; a KITTI calib.txt for "kitti".
  std::string calibrationPath;
  // "7scenes": the depth images were recorded in the Kinect's depth camera, not registered to
  // the colour images. false (default): used as recorded, with the dataset's (depth camera's)
  // intrinsics for both images, the colour pixels then taking the depth of a point up to ~15 px
  // away. true: each one is registered to the colour camera when it is read, with the published
  // calibration or calibrationPath's colour model (see SevenScenesReader.cpp for why it is not
  // the default).
  bool registerDepth = false;
  // "carmen": readings at or beyond this range (metres) are no-returns. 0 = from the log: a
  // PARAM naming a laser max range, else the sensor's saturation value found in the data (see
  // CarmenReader.cpp), capped at 80 m.
  double scanRangeMax = 0.0;
};

class DatasetReader {
 public:
  virtual ~DatasetReader() = default;
  // Format name as given to openDatasetReader ("carmen", "7scenes", "tum", "euroc", "kitti",
  // "images", "sim").
  virtual std::string format() const = 0;
  // Reads the next record in time order. Returns false at the end of the dataset. Throws
  // FormatError naming the file (and line, for text files) on malformed input.
  virtual bool next(DatasetRecord& record) = 0;
  // Number of kFrame records the stream will yield (after options), or -1 if unknown without
  // reading it all (e.g. a compressed log).
  virtual int frameCount() const { return -1; }
};

// Opens a dataset. format: "carmen" (.clf or .clf.bz2 file), "7scenes" (folder), "tum"
// (folder), "euroc" (folder holding mav0/), "kitti" (sequence folder), "images" (folder),
// "sim" (folder written by rtabmap-sim). Throws FormatError for an unknown format or a path
// that does not hold that layout, with what was expected.
std::unique_ptr<DatasetReader> openDatasetReader(const std::string& format, const std::string& path,
                                                 const DatasetReaderOptions& options = {});
// The formats openDatasetReader accepts, sorted.
std::vector<std::string> datasetFormats();

// Each reader registers its format from its own .cpp (a namespace-scope
//   const bool kRegistered = registerDatasetFormat("sim", &openSimDataset);
// ), so openDatasetReader needs no list of readers and a new layout is one new file.
// Registering a name twice is a programming error (std::logic_error).
using DatasetReaderFactory = std::function<std::unique_ptr<DatasetReader>(
    const std::string& path, const DatasetReaderOptions& options)>;
bool registerDatasetFormat(const std::string& name, DatasetReaderFactory factory);

}  // namespace rtabmap

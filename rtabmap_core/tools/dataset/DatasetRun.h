#pragma once
// rtabmap-dataset as a pipeline of stages over a dataset stream, each a small class, so the
// SLAM issue can add its mapping stage between odometry and the summary:
//   reader (eval/DatasetReader) -> OdometryStage -> RunStatistics -> outputs (odom.tum, JSON)
#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/eval/Trajectory.h"
#include "rtabmap_core/odometry/Odometry.h"

namespace rtabmap::tools::dataset {

struct RunOptions {
  std::string format;  // openDatasetReader format
  std::string path;
  std::string outputDir;
  std::optional<Odometry::Type> odometry;  // none: from Odom/Strategy and Reg/Strategy
  ParametersMap parameters;
  DatasetReaderOptions reader;
  bool wheelOdometryGuess = false;  // --guess-odom
  bool ateInCameraFrame = false;    // --ate-frame camera
  std::string framesCsv;            // --frames-csv: one line of odometry figures per frame
  std::string updatesCsv;           // --updates-csv: one line of SLAM figures per map update
  // --odom wheel: the dataset's own wheel odometry is the odometry (no registration).
  bool wheelOdometry = false;
  // Mapping (--slam, --continue, --localization): Rtabmap over the odometry's frames.
  bool slam = false;
  bool continueDatabase = false;
  bool localization = false;
};

// One frame after odometry.
struct FrameResult {
  int id = 0;
  double stamp = 0.0;
  Transform pose;         // odometry pose of the base frame, null when lost
  Transform groundTruth;  // base frame, null when unknown
  Transform cameraLocal;  // base -> (left) camera optical frame, null without camera
  OdometryInfo info;
};

// Stage: odometry of each frame record, with the dataset's wheel odometry as motion guess when
// asked (the motion of the wheel odometry since the previous frame).
class OdometryStage {
 public:
  explicit OdometryStage(const RunOptions& options);
  // Consumes kOdometry records (wheel odometry between frames) and kImu records (given to
  // odometry, --imu); returns a result for kFrame
  // records only.
  std::optional<FrameResult> process(DatasetRecord& record);
  const Odometry& odometry() const { return *odometry_; }

 private:
  std::unique_ptr<Odometry> odometry_;
  bool wheelGuess_;
  Transform latestWheel_;     // latest wheel odometry pose seen (frame or kOdometry record)
  Transform previousWheel_;   // wheel odometry pose at the previous frame
  bool wheelOnly_;
  int wheelFrames_ = 0;
  double previousStamp_ = 0.0;
  double wheelDistance_ = 0.0;
};

// Covariance of a wheel-odometry increment: a floor plus a part growing with the motion
// (translation 5% of the distance, rotation 5% of the turn plus 2 degrees per metre).
Eigen::Matrix<double, 6, 6> wheelIncrementCovariance(const Transform& motion);

// What the outputs keep of a frame: its trajectories and odometry figures. Not the whole
// OdometryInfo: kept for every frame of a two-hour run, it made the tool grow ~1.4 KB a frame,
// which --updates-csv's resident sizes then counted as if the map had grown.
struct FrameRecord {
  explicit FrameRecord(const FrameResult& frame);
  int id;
  double stamp;
  Transform pose, groundTruth, cameraLocal;  // as in FrameResult
  bool lost, keyFrameAdded, autoReset, guessFromImu;
  int features, matches, inliers, localMapSize;
  double timeTotalMs;
  double distanceTravelled;
  std::string lostReason;
};

// Stage: accumulates the results: trajectories, timings, counts; writes and summarises them.
class RunStatistics {
 public:
  explicit RunStatistics(const RunOptions& options) : options_(options) {}
  void add(const FrameResult& frame);
  // DIR/odom.tum (always, lost frames skipped), DIR/gt.tum when there is ground truth, and the
  // per-frame CSV when asked.
  void writeOutputs() const;
  nlohmann::json toJson() const;
  void printText(std::ostream& out) const;
  size_t frames() const { return frames_.size(); }
  void setApproach(const std::string& name) { approach_ = name; }
  void setSlam(const nlohmann::json& slam) { slam_ = slam; }

 private:
  void writeFramesCsv() const;
  Trajectory estimate(bool cameraFrame) const;
  Trajectory groundTruth(bool cameraFrame) const;

  RunOptions options_;
  std::string approach_;
  std::vector<FrameRecord> frames_;
  nlohmann::json slam_;  // the mapping stage's figures (empty without --slam)
};

// Runs the stages over the whole dataset; `progress` (may be empty) is called after each frame
// with (frames done, frames expected or -1).
RunStatistics runDataset(const RunOptions& options, const std::function<void(size_t, int)>& progress);

}  // namespace rtabmap::tools::dataset

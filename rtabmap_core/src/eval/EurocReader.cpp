// "euroc": an EuRoC MAV sequence in the ASL folder layout (Burri et al., IJRR 2016). The path is
// the folder holding mav0/ (or mav0/ itself):
//   mav0/cam0/data.csv, mav0/cam1/data.csv   `timestamp_ns,filename` per image
//   mav0/cam{0,1}/data/<ns>.png               752x480 grey, raw (distorted)
//   mav0/cam{0,1}/sensor.yaml                 intrinsics [fu fv cu cv], radial-tangential
//                                             distortion, resolution, T_BS (body -> sensor)
//   mav0/imu0/data.csv                        `ns, w_x w_y w_z (rad/s), a_x a_y a_z (m/s^2)`
//   mav0/imu0/sensor.yaml (optional)          T_BS, noise densities, rate
//
// Frames: stereo pairs, the cam0 and cam1 images with the same timestamp (others are dropped),
// rectified with StereoCameraModel::fromRawCalibration from the two sensor.yaml files: left grey
// and right grey rectified images. The base frame is the body frame: the model's local
// transform is body -> rectified left optical frame (T_BS of cam0 times the rectification
// rotation).
//
// IMU: a kImu record per imu0 line, in the body frame's IMU (local transform = imu0's T_BS,
// identity when imu0/sensor.yaml is absent: in EuRoC the body frame is the IMU frame). With
// imu0/sensor.yaml, covariances are the noise densities squared times the rate (the
// discrete-time variances); without, they are zero (unknown). Orientation: unknown. An IMU
// sample with the stamp of a frame comes before the frame; samples after the last frame are
// not read (the stream ends with its last frame).
//
// Ground truth: a trajectory of the body frame, in order DatasetReaderOptions::groundTruthPath;
// a `groundtruth*.txt` (TUM format) file in the dataset folder or its parent; mav0/
// state_groundtruth_estimate0/data.csv (EuRoC's own). It is interpolated at each frame stamp
// (linear / slerp) between samples at most 0.1 s apart, and given as is: the pose of the base
// (= body) frame, so groundTruth * localTransform is the rectified left camera's pose.
//
// Stamps: nanoseconds / 1e9 (seconds; a double keeps them to ~0.2 microseconds).
#include <opencv2/core.hpp>
#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ReaderSupport.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/eval/Trajectory.h"
#include "rtabmap_core/geometry/StereoCameraModel.h"

namespace rtabmap {
namespace {

using eval_detail::joinPath;
using eval_detail::throwAt;

constexpr double kMaxGroundTruthGap = 0.1;

struct EurocCamera {
  cv::Mat K, D;
  cv::Size size;
  Transform T_BS;
};

Transform readTBS(const cv::FileNode& node, const std::string& path) {
  std::vector<double> data;
  if (node.isMap()) node["data"] >> data;
  if (data.size() != 16) throw FormatError(path + ": T_BS must be a 4x4 matrix (data: 16 numbers)");
  return Transform::fromArray12(data.data());
}

EurocCamera readCamera(const std::string& path) {
  if (!eval_detail::isFile(path)) throw FormatError("euroc: missing " + path);
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ);
  } catch (const cv::Exception& e) {
    throw FormatError(path + ": cannot parse (" + e.what() + ")");
  }
  if (!fs.isOpened()) throw FormatError(path + ": cannot open");
  std::vector<double> intr, dist;
  std::vector<int> res;
  fs["intrinsics"] >> intr;
  fs["distortion_coefficients"] >> dist;
  fs["resolution"] >> res;
  std::string model;
  fs["distortion_model"] >> model;
  if (intr.size() != 4) throw FormatError(path + ": intrinsics must be [fu, fv, cu, cv]");
  if (res.size() != 2 || res[0] <= 0 || res[1] <= 0) throw FormatError(path + ": resolution must be [width, height]");
  if (!model.empty() && model != "radial-tangential" && model != "radtan" && model != "plumb_bob") {
    throw FormatError(path + ": distortion_model \"" + model +
                      "\" is not supported (radial-tangential only)");
  }
  if (dist.size() != 4 && dist.size() != 5) {
    throw FormatError(path + ": distortion_coefficients must hold 4 (k1 k2 p1 p2) or 5 values");
  }
  EurocCamera c;
  c.K = (cv::Mat_<double>(3, 3) << intr[0], 0, intr[2], 0, intr[1], intr[3], 0, 0, 1);
  c.D = cv::Mat(dist, true).reshape(1, 1);
  c.size = cv::Size(res[0], res[1]);
  c.T_BS = readTBS(fs["T_BS"], path);
  return c;
}

// `ns,filename` lines of a camera's data.csv.
std::vector<std::pair<long long, std::string>> readImageList(const std::string& path) {
  eval_detail::TextLineReader in(path);
  std::vector<std::pair<long long, std::string>> list;
  std::string line;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    const auto f = eval_detail::splitFields(line, true);
    if (f.size() != 2) throwAt(path, in.lineNumber(), "expected `timestamp_ns,filename`");
    list.emplace_back(eval_detail::parseInteger(f[0], path, in.lineNumber(), "timestamp [ns]"), std::string(f[1]));
  }
  std::stable_sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return list;
}

// groundtruth*.txt in the dataset folder, else the only one in its parent (a parent holding
// several sequences' files is ambiguous), else EuRoC's own csv.
std::string findGroundTruth(const std::string& root, const std::string& mav0) {
  const std::string dirs[2] = {root, joinPath(root, "..")};
  for (int d = 0; d < 2; ++d) {
    if (!eval_detail::isDirectory(dirs[d])) continue;
    std::vector<std::string> found;
    for (const std::string& name : eval_detail::listFiles(dirs[d], {".txt"})) {
      if (name.compare(0, 11, "groundtruth") == 0) found.push_back(joinPath(dirs[d], name));
    }
    if (found.size() == 1 || (d == 0 && !found.empty())) return found.front();
  }
  const std::string native = joinPath(mav0, "state_groundtruth_estimate0/data.csv");
  if (eval_detail::isFile(native)) return native;
  return "";
}

class EurocReader : public eval_detail::WindowedReader {
 public:
  EurocReader(const std::string& path, const DatasetReaderOptions& options)
      : WindowedReader(options) {
    std::string root = path;
    mav0_ = joinPath(path, "mav0");
    if (!eval_detail::isDirectory(mav0_)) {
      if (eval_detail::isDirectory(joinPath(path, "cam0"))) {
        mav0_ = path;
        root = joinPath(path, "..");
      } else {
        throw FormatError("euroc: " + path + " holds no mav0/ folder (expected mav0/cam0, mav0/cam1, "
                          "mav0/imu0)");
      }
    }
    const EurocCamera c0 = readCamera(joinPath(mav0_, "cam0/sensor.yaml"));
    const EurocCamera c1 = readCamera(joinPath(mav0_, "cam1/sensor.yaml"));
    if (c0.size != c1.size) throw FormatError("euroc: cam0 and cam1 resolutions differ");
    // x_right = R x_left + T: the left camera frame expressed in the right camera frame.
    const Eigen::Matrix4d m = (c1.T_BS.inverse() * c0.T_BS).toMatrix4d();
    cv::Mat R(3, 3, CV_64FC1), T(3, 1, CV_64FC1);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) R.at<double>(i, j) = m(i, j);
      T.at<double>(i) = m(i, 3);
    }
    stereo_ = StereoCameraModel::fromRawCalibration("euroc", c0.size, c0.K, c0.D, c1.K, c1.D, R, T, c0.T_BS);
    if (options.images) stereo_.initRectificationMap();

    const auto left = readImageList(joinPath(mav0_, "cam0/data.csv"));
    const auto right = readImageList(joinPath(mav0_, "cam1/data.csv"));
    std::map<long long, std::string> rightByStamp(right.begin(), right.end());
    for (const auto& [ns, file] : left) {
      auto it = rightByStamp.find(ns);
      if (it != rightByStamp.end()) frames_.push_back({ns, file, it->second});
    }
    if (frames_.empty()) throw FormatError("euroc: " + mav0_ + ": no cam0/cam1 pair with equal timestamps");
    if (frames_.size() < left.size()) {
      RTABMAP_INFO("euroc: " << (left.size() - frames_.size()) << " cam0 images without a cam1 image "
                             << "of the same stamp are dropped");
    }

    imuPath_ = joinPath(mav0_, "imu0/data.csv");
    if (options.imu && eval_detail::isFile(imuPath_)) {
      imu_ = std::make_unique<eval_detail::TextLineReader>(imuPath_);
      const std::string imuYaml = joinPath(mav0_, "imu0/sensor.yaml");
      if (eval_detail::isFile(imuYaml)) {
        cv::FileStorage fs(imuYaml, cv::FileStorage::READ);
        if (!fs.isOpened()) throw FormatError(imuYaml + ": cannot open");
        imuTemplate_.localTransform = readTBS(fs["T_BS"], imuYaml);
        double gyro = 0.0, acc = 0.0, rate = 0.0;
        fs["gyroscope_noise_density"] >> gyro;
        fs["accelerometer_noise_density"] >> acc;
        fs["rate_hz"] >> rate;
        if (rate > 0.0) {
          imuTemplate_.angularVelocityCovariance = Eigen::Matrix3d::Identity() * gyro * gyro * rate;
          imuTemplate_.linearAccelerationCovariance = Eigen::Matrix3d::Identity() * acc * acc * rate;
        }
      }
    }

    const std::string gt = !options.groundTruthPath.empty() ? options.groundTruthPath : findGroundTruth(root, mav0_);
    if (!gt.empty()) {
      groundTruth_ = readTrajectory(gt);
      groundTruth_.sortByStamp();
    } else {
      RTABMAP_INFO("euroc: " << path << ": no ground truth found (groundtruth*.txt beside the folder "
                             << "or mav0/state_groundtruth_estimate0/data.csv)");
    }
  }

  std::string format() const override { return "euroc"; }
  int frameCount() const override { return windowed(static_cast<int>(frames_.size())); }

 protected:
  bool readNext(DatasetRecord& record) override {
    // IMU samples up to each frame; none after the last frame (the stream ends with it).
    if (cursor_ >= frames_.size()) return false;
    if (imu_ && !imuPending_ && !imuDone_) readImu();
    if (imuPending_ && imuStampNs_ <= frames_[cursor_].ns) {
      record = std::move(imuRecord_);
      imuRecord_ = DatasetRecord();
      imuPending_ = false;
      return true;
    }
    const size_t i = cursor_++;
    const Frame& f = frames_[i];
    record = DatasetRecord();
    record.kind = DatasetRecord::Kind::kFrame;
    record.stamp = static_cast<double>(f.ns) * 1e-9;
    if (nextFrameSkipped()) return true;
    if (options().images) {
      const cv::Mat rawLeft = eval_detail::readImage(joinPath(mav0_, "cam0/data/" + f.left), cv::IMREAD_GRAYSCALE);
      const cv::Mat rawRight = eval_detail::readImage(joinPath(mav0_, "cam1/data/" + f.right), cv::IMREAD_GRAYSCALE);
      cv::Mat left, right;
      stereo_.rectify(rawLeft, rawRight, left, right);
      record.data = SensorData(left, right, stereo_, static_cast<int>(i) + 1, record.stamp);
    } else {
      record.data.setId(static_cast<int>(i) + 1);
      record.data.setStamp(record.stamp);
    }
    if (!groundTruth_.empty()) {
      const Transform body = groundTruth_.interpolate(record.stamp, kMaxGroundTruthGap);
      if (!body.isNull()) record.data.setGroundTruth(body);
    }
    return true;
  }

 private:
  void readImu() {
    std::string line;
    while (imu_->next(line)) {
      if (eval_detail::isCommentOrBlank(line)) continue;
      const long n = imu_->lineNumber();
      const auto f = eval_detail::splitFields(line, true);
      if (f.size() != 7) {
        throwAt(imuPath_, n, "expected `timestamp_ns, w_x, w_y, w_z, a_x, a_y, a_z`, got " +
                                 std::to_string(f.size()) + " fields");
      }
      const long long ns = eval_detail::parseInteger(f[0], imuPath_, n, "timestamp [ns]");
      if (ns < lastImuNs_) {
        throwAt(imuPath_, n, "timestamps go back in time");
      }
      IMU imu = imuTemplate_;
      imu.angularVelocity = {eval_detail::parseNumber(f[1], imuPath_, n, "w_x"),
                             eval_detail::parseNumber(f[2], imuPath_, n, "w_y"),
                             eval_detail::parseNumber(f[3], imuPath_, n, "w_z")};
      imu.linearAcceleration = {eval_detail::parseNumber(f[4], imuPath_, n, "a_x"),
                                eval_detail::parseNumber(f[5], imuPath_, n, "a_y"),
                                eval_detail::parseNumber(f[6], imuPath_, n, "a_z")};
      imuRecord_ = DatasetRecord();
      imuRecord_.kind = DatasetRecord::Kind::kImu;
      imuRecord_.stamp = static_cast<double>(ns) * 1e-9;
      imuRecord_.data.setStamp(imuRecord_.stamp);
      imuRecord_.data.setIMU(imu);
      imuStampNs_ = ns;
      lastImuNs_ = ns;
      imuPending_ = true;
      return;
    }
    imuDone_ = true;
  }

  struct Frame {
    long long ns;
    std::string left;
    std::string right;
  };
  std::string mav0_;
  StereoCameraModel stereo_;
  std::vector<Frame> frames_;
  size_t cursor_ = 0;
  std::string imuPath_;
  std::unique_ptr<eval_detail::TextLineReader> imu_;
  IMU imuTemplate_;
  DatasetRecord imuRecord_;
  long long imuStampNs_ = 0;
  long long lastImuNs_ = std::numeric_limits<long long>::min();
  bool imuPending_ = false;
  bool imuDone_ = false;
  Trajectory groundTruth_;
};

[[maybe_unused]] const bool kRegistered = registerDatasetFormat(
    "euroc", [](const std::string& path, const DatasetReaderOptions& options) {
      return std::unique_ptr<DatasetReader>(new EurocReader(path, options));
    });

}  // namespace
}  // namespace rtabmap

// "7scenes": a Microsoft 7-Scenes sequence folder: frame-NNNNNN.color.png|jpg (640x480 BGR),
// frame-NNNNNN.depth.png (16-bit mm, 65535 = invalid), frame-NNNNNN.pose.txt (4x4
// camera-to-world, KinectFusion's pseudo ground truth), camera-intrinsics.txt (3x3 K).
//
// Stamps: 7-Scenes has none. They are synthesised at 30 Hz (the Kinect's rate;
// DatasetReaderOptions::frameRate overrides it): stamp = N / 30 for frame N, so a frame keeps
// its stamp whatever startFrame is.
//
// Frames and ground truth. The camera is hand-held: there is no robot base, so the base frame
// is put at the camera, with the ROS body axes (x forward, y left, z up), and the camera model's
// local transform is CameraModel::opticalRotation() (base -> optical). The pose files give the
// optical frame in the world, so the ground truth of a frame is
//     groundTruth = world_T_optical * opticalRotation()^-1   (the base's pose)
// i.e. groundTruth * localTransform is the file's pose exactly, as for the TUM reader, and a
// SLAM run's base trajectory compares with it directly. The world frame stays KinectFusion's
// (ATE aligns it anyway). Pose files with non-finite values (lost tracking) give a null
// ground truth.
//
// Depth: invalid pixels (65535) are set to 0, the invalid value of ROS depth images. 7-Scenes'
// depth is not registered to its colour image (different sensors of the Kinect); the dataset
// gives one intrinsics file, used for both.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <charconv>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ReaderSupport.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/geometry/CameraModel.h"

namespace rtabmap {
namespace {

using eval_detail::joinPath;
using eval_detail::throwAt;

struct FrameFiles {
  std::string color;
  std::string depth;
  std::string pose;
};

// "frame-000123.color.jpg" -> 123 and the suffix after the number; false if not that form.
bool parseFrameName(const std::string& name, long& number, std::string& suffix) {
  if (name.compare(0, 6, "frame-") != 0) return false;
  size_t i = 6;
  while (i < name.size() && std::isdigit(static_cast<unsigned char>(name[i]))) ++i;
  if (i == 6 || i >= name.size() || name[i] != '.') return false;
  const auto [ptr, ec] = std::from_chars(name.data() + 6, name.data() + i, number);
  if (ec != std::errc()) return false;
  suffix = name.substr(i + 1);
  return true;
}

CameraModel readIntrinsics(const std::string& path, const cv::Size& size) {
  eval_detail::TextLineReader in(path);
  std::vector<double> v;
  std::string line;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    for (auto f : eval_detail::splitFields(line, true)) {
      v.push_back(eval_detail::parseNumber(f, path, in.lineNumber(), "intrinsics value"));
    }
  }
  if (v.size() != 9) {
    throw FormatError(path + ": expected a 3x3 intrinsics matrix (9 numbers), got " +
                      std::to_string(v.size()));
  }
  if (v[0] <= 0.0 || v[4] <= 0.0) throw FormatError(path + ": fx and fy must be positive");
  return CameraModel(v[0], v[4], v[2], v[5], CameraModel::opticalRotation(), 0.0, size);
}

// The 4x4 camera-to-world matrix; null if a value is not finite (lost tracking).
Transform readPose(const std::string& path) {
  eval_detail::TextLineReader in(path);
  std::vector<double> v;
  std::string line;
  bool finite = true;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    for (auto f : eval_detail::splitFields(line, true)) {
      double x = 0.0;
      if (!eval_detail::tryParseNumber(f, x)) {
        const std::string t = eval_detail::toLower(std::string(f));
        if (t == "inf" || t == "-inf" || t == "nan" || t == "-nan") {
          finite = false;
        } else {
          throwAt(path, in.lineNumber(), "pose value: '" + std::string(f) + "' is not a number");
        }
      }
      v.push_back(x);
    }
  }
  if (v.size() != 16 && v.size() != 12) {
    throw FormatError(path + ": expected a 4x4 pose matrix (16 numbers), got " + std::to_string(v.size()));
  }
  if (!finite) return Transform();
  return Transform::fromArray12(v.data());
}

class SevenScenesReader : public eval_detail::WindowedReader {
 public:
  SevenScenesReader(const std::string& path, const DatasetReaderOptions& options)
      : WindowedReader(options), path_(path) {
    if (!eval_detail::isDirectory(path)) {
      throw FormatError("7scenes: " + path + " is not a folder (expected frame-N.color.jpg, "
                        "frame-N.depth.png, frame-N.pose.txt)");
    }
    std::map<long, FrameFiles> frames;
    for (const std::string& name : eval_detail::listFiles(path, {})) {
      long n = 0;
      std::string suffix;
      if (!parseFrameName(name, n, suffix)) continue;
      if (suffix == "color.png" || suffix == "color.jpg") {
        frames[n].color = name;
      } else if (suffix == "depth.png") {
        frames[n].depth = name;
      } else if (suffix == "pose.txt") {
        frames[n].pose = name;
      }
    }
    for (const auto& [n, files] : frames) {
      if (!files.color.empty() || !files.depth.empty()) {
        numbers_.push_back(n);
        files_.push_back(files);
      }
    }
    if (numbers_.empty()) {
      throw FormatError("7scenes: " + path + " holds no frame-N.color.(jpg|png) or frame-N.depth.png");
    }
    rate_ = options.frameRate > 0.0 ? options.frameRate : 30.0;
    const cv::Size size(640, 480);
    if (!options.calibrationPath.empty()) {
      model_ = CameraModel::load(options.calibrationPath);
    } else if (eval_detail::isFile(joinPath(path, "camera-intrinsics.txt"))) {
      model_ = readIntrinsics(joinPath(path, "camera-intrinsics.txt"), size);
    } else {
      RTABMAP_WARN("7scenes: " << path << " has no camera-intrinsics.txt: using the 7-Scenes "
                               << "intrinsics fx = fy = 585, cx = 320, cy = 240");
      model_ = CameraModel(585.0, 585.0, 320.0, 240.0, CameraModel::opticalRotation(), 0.0, size);
    }
  }

  std::string format() const override { return "7scenes"; }
  int frameCount() const override { return windowed(static_cast<int>(numbers_.size())); }

 protected:
  bool readNext(DatasetRecord& record) override {
    if (cursor_ >= numbers_.size()) return false;
    const size_t i = cursor_++;
    const long n = numbers_[i];
    const FrameFiles& files = files_[i];
    record = DatasetRecord();
    record.kind = DatasetRecord::Kind::kFrame;
    record.stamp = static_cast<double>(n) / rate_;
    if (nextFrameSkipped()) return true;

    cv::Mat rgb, depth;
    if (options().images) {
      if (!files.color.empty()) rgb = eval_detail::readImage(joinPath(path_, files.color), cv::IMREAD_COLOR);
      if (!files.depth.empty()) {
        const std::string p = joinPath(path_, files.depth);
        depth = eval_detail::readImage(p, cv::IMREAD_UNCHANGED);
        if (depth.type() != CV_16UC1) {
          throw FormatError(p + ": expected a 16-bit single-channel depth image (mm)");
        }
        depth.setTo(0, depth == 65535);
      }
    }
    CameraModel model = model_;
    const cv::Mat& ref = rgb.empty() ? depth : rgb;
    if (!ref.empty() && model.imageSize() != ref.size()) model.setImageSize(ref.size());
    if (!rgb.empty() || !depth.empty()) {
      record.data = SensorData(rgb, depth, model, static_cast<int>(n) + 1, record.stamp);
    } else {
      record.data.setId(static_cast<int>(n) + 1);
      record.data.setStamp(record.stamp);
    }
    if (!files.pose.empty()) {
      const Transform cameraPose = readPose(joinPath(path_, files.pose));
      if (!cameraPose.isNull()) {
        record.data.setGroundTruth(cameraPose * CameraModel::opticalRotation().inverse());
      }
    }
    return true;
  }

 private:
  std::string path_;
  std::vector<long> numbers_;
  std::vector<FrameFiles> files_;
  CameraModel model_;
  double rate_ = 30.0;
  size_t cursor_ = 0;
};

[[maybe_unused]] const bool kRegistered = registerDatasetFormat(
    "7scenes", [](const std::string& path, const DatasetReaderOptions& options) {
      return std::unique_ptr<DatasetReader>(new SevenScenesReader(path, options));
    });

}  // namespace
}  // namespace rtabmap

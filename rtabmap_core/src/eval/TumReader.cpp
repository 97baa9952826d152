// "tum": a TUM RGB-D benchmark sequence folder (Sturm et al., IROS 2012): rgb.txt and
// depth.txt (`stamp relative/path.png` per line, '#' comments), rgb/ and depth/ images,
// groundtruth.txt (`stamp tx ty tz qx qy qz qw`, the colour camera's optical frame in the
// motion-capture world).
//
// Frames: each rgb image with the depth image nearest in time, at most 20 ms away (each depth
// used once, closest pairs first, as the benchmark's associate.py); an rgb image without one is
// dropped. Stamp = the rgb stamp. Depth: 16-bit, 5000 per metre in the files, converted to
// CV_16UC1 millimetres (value / 5, rounded; 0 = invalid).
//
// Intrinsics, in order: DatasetReaderOptions::calibrationPath, a ROS camera_info YAML in the
// folder (camera_info.yaml, calibration.yaml, rgb.yaml), else the benchmark's published values
// chosen by the folder name: "freiburg1"/"fr1" -> 517.3 516.5 318.6 255.3, "freiburg2"/"fr2"
// -> 520.9 521.0 325.1 249.7, "freiburg3"/"fr3" -> 535.4 539.2 320.1 247.6; other names get the
// benchmark's recommended default for unknown Kinects (the ROS default) 525.0 525.0 319.5 239.5.
// The fr1/fr2 distortion coefficients are not applied: the depth images were registered to the
// distorted colour images by the sensor itself, and undistorting one without the other would
// misalign them. (A YAML calibration with distortion rectifies colour and depth alike.)
//
// Ground truth: interpolated at the rgb stamp (linear / slerp) between the two nearest
// samples when they are at most 0.1 s apart (motion-capture dropouts give a null ground
// truth), then expressed as the pose of the base frame, as for 7-Scenes: the base is at the
// camera with ROS body axes, the camera's local transform is CameraModel::opticalRotation(), and
// groundTruth = world_T_optical * opticalRotation()^-1.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "ReaderSupport.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/eval/Trajectory.h"
#include "rtabmap_core/eval/TrajectoryError.h"
#include "rtabmap_core/geometry/CameraModel.h"

namespace rtabmap {
namespace {

using eval_detail::joinPath;
using eval_detail::throwAt;

constexpr double kMaxAssociationDifference = 0.02;
constexpr double kMaxGroundTruthGap = 0.1;

struct ListEntry {
  double stamp = 0.0;
  std::string file;
};

std::vector<ListEntry> readList(const std::string& path) {
  eval_detail::TextLineReader in(path);
  std::vector<ListEntry> entries;
  std::string line;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    const auto f = eval_detail::splitFields(line);
    if (f.size() != 2) {
      throwAt(path, in.lineNumber(), "expected `stamp file`, got " + std::to_string(f.size()) + " fields");
    }
    entries.push_back({eval_detail::parseNumber(f[0], path, in.lineNumber(), "stamp"), std::string(f[1])});
  }
  std::stable_sort(entries.begin(), entries.end(),
                   [](const ListEntry& a, const ListEntry& b) { return a.stamp < b.stamp; });
  return entries;
}

Trajectory stampsOnly(const std::vector<ListEntry>& entries) {
  Trajectory t;
  for (const auto& e : entries) t.add(e.stamp, Transform::Identity());
  return t;
}

CameraModel freiburgIntrinsics(const std::string& folder) {
  std::string name = eval_detail::toLower(std::filesystem::path(folder).lexically_normal().string());
  while (!name.empty() && name.back() == '/') name.pop_back();
  name = eval_detail::fileName(name);
  const cv::Size size(640, 480);
  const Transform optical = CameraModel::opticalRotation();
  if (name.find("freiburg1") != std::string::npos || name.find("fr1") != std::string::npos) {
    return CameraModel(517.3, 516.5, 318.6, 255.3, optical, 0.0, size);
  }
  if (name.find("freiburg2") != std::string::npos || name.find("fr2") != std::string::npos) {
    return CameraModel(520.9, 521.0, 325.1, 249.7, optical, 0.0, size);
  }
  if (name.find("freiburg3") != std::string::npos || name.find("fr3") != std::string::npos) {
    return CameraModel(535.4, 539.2, 320.1, 247.6, optical, 0.0, size);
  }
  RTABMAP_INFO("tum: " << folder << ": no freiburg1/2/3 in the folder name and no calibration "
                       << "file: using the default intrinsics 525.0 525.0 319.5 239.5");
  return CameraModel(525.0, 525.0, 319.5, 239.5, optical, 0.0, size);
}

class TumReader : public eval_detail::WindowedReader {
 public:
  TumReader(const std::string& path, const DatasetReaderOptions& options)
      : WindowedReader(options), path_(path) {
    const std::string rgbList = joinPath(path, "rgb.txt");
    const std::string depthList = joinPath(path, "depth.txt");
    if (!eval_detail::isDirectory(path) || !eval_detail::isFile(rgbList)) {
      throw FormatError("tum: " + path + " is not a TUM RGB-D folder (expected rgb.txt, depth.txt, "
                        "groundtruth.txt)");
    }
    const std::vector<ListEntry> rgb = readList(rgbList);
    if (eval_detail::isFile(depthList)) {
      const std::vector<ListEntry> depth = readList(depthList);
      for (const auto& [i, j] : associateByStamp(stampsOnly(rgb), stampsOnly(depth), kMaxAssociationDifference)) {
        frames_.push_back({rgb[i].stamp, rgb[i].file, depth[j].file});
      }
      if (frames_.size() < rgb.size()) {
        RTABMAP_INFO("tum: " << (rgb.size() - frames_.size()) << " of " << rgb.size()
                             << " rgb images have no depth image within 20 ms and are dropped");
      }
    } else {
      for (const auto& e : rgb) frames_.push_back({e.stamp, e.file, ""});
    }
    if (frames_.empty()) throw FormatError("tum: " + path + ": no frame (rgb.txt is empty or nothing associates)");

    if (!options.calibrationPath.empty()) {
      model_ = CameraModel::load(options.calibrationPath);
    } else {
      bool found = false;
      for (const char* name : {"camera_info.yaml", "calibration.yaml", "rgb.yaml"}) {
        if (eval_detail::isFile(joinPath(path, name))) {
          model_ = CameraModel::load(joinPath(path, name));
          found = true;
          break;
        }
      }
      if (!found) model_ = freiburgIntrinsics(path);
    }
    rectify_ = model_.isValidForRectification() && !model_.D_raw().empty() &&
               cv::countNonZero(model_.D_raw()) > 0;

    std::string gt = options.groundTruthPath;
    if (gt.empty() && eval_detail::isFile(joinPath(path, "groundtruth.txt"))) gt = joinPath(path, "groundtruth.txt");
    if (!gt.empty()) {
      groundTruth_ = readTrajectory(gt, TrajectoryFormat::kTum);
      groundTruth_.sortByStamp();
    }
  }

  std::string format() const override { return "tum"; }
  int frameCount() const override { return windowed(static_cast<int>(frames_.size())); }

 protected:
  bool readNext(DatasetRecord& record) override {
    if (cursor_ >= frames_.size()) return false;
    const size_t i = cursor_++;
    const Frame& f = frames_[i];
    record = DatasetRecord();
    record.kind = DatasetRecord::Kind::kFrame;
    record.stamp = f.stamp;
    if (nextFrameSkipped()) return true;
    cv::Mat rgb, depth;
    if (options().images) {
      rgb = eval_detail::readImage(joinPath(path_, f.rgb), cv::IMREAD_COLOR);
      if (!f.depth.empty()) {
        const std::string p = joinPath(path_, f.depth);
        const cv::Mat raw = eval_detail::readImage(p, cv::IMREAD_UNCHANGED);
        if (raw.type() != CV_16UC1) throw FormatError(p + ": expected a 16-bit single-channel depth image");
        raw.convertTo(depth, CV_16UC1, 1000.0 / 5000.0);
      }
      if (rectify_) {
        rgb = model_.rectifyImage(rgb);
        if (!depth.empty()) depth = model_.rectifyDepth(depth);
      }
    }
    CameraModel model = model_;
    if (!rgb.empty() && model.imageSize() != rgb.size()) model.setImageSize(rgb.size());
    if (!rgb.empty()) {
      record.data = SensorData(rgb, depth, model, static_cast<int>(i) + 1, f.stamp);
    } else {
      record.data.setId(static_cast<int>(i) + 1);
      record.data.setStamp(f.stamp);
    }
    if (!groundTruth_.empty()) {
      const Transform cameraPose = groundTruth_.interpolate(f.stamp, kMaxGroundTruthGap);
      if (!cameraPose.isNull()) {
        record.data.setGroundTruth(cameraPose * CameraModel::opticalRotation().inverse());
      }
    }
    return true;
  }

 private:
  struct Frame {
    double stamp;
    std::string rgb;
    std::string depth;
  };
  std::string path_;
  std::vector<Frame> frames_;
  CameraModel model_;
  bool rectify_ = false;
  Trajectory groundTruth_;
  size_t cursor_ = 0;
};

[[maybe_unused]] const bool kRegistered = registerDatasetFormat(
    "tum", [](const std::string& path, const DatasetReaderOptions& options) {
      return std::unique_ptr<DatasetReader>(new TumReader(path, options));
    });

}  // namespace
}  // namespace rtabmap

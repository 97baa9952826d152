// "kitti": a KITTI odometry sequence (Geiger et al., CVPR 2012). The path is a sequence folder:
//   image_0/NNNNNN.png, image_1/NNNNNN.png   rectified grey stereo pair (left, right)
//   velodyne/NNNNNN.bin                       HDL-64E scans, float32 x y z intensity per point
//   calib.txt                                 P0..P3 (3x4 rectified projections), Tr (velodyne ->
//                                             cam0, 3x4)
//   times.txt                                 one stamp (s) per frame
// and the ground truth in the benchmark's poses/NN.txt (NN = the sequence folder's name, found
// at <path>/../../poses/NN.txt), <path>/poses.txt, a file of the folder whose name contains
// "pose" (.txt or .csv), or DatasetReaderOptions::groundTruthPath: one 3x4 row-major pose of
// cam0 (optical frame) in the first cam0 frame per row, blank- or comma-separated; row n
// (0-based) is frame n.
//
// A folder of velodyne scans only (NNNNNN.bin files directly in it, any subset of a
// sequence, e.g. 000094.bin 000095.bin) is read the same way: the frames are the files
// present, frame n reading row n of the poses file.
//
// Frames: frame n (id n + 1) has the stereo pair when image_0/1 exist (needs calib.txt), and
// the scan as an XYZI LaserScan (maxPoints = its point count, range max 120 m, the HDL-64E's).
// Stamps: times.txt, else n / 10 Hz (DatasetReaderOptions::frameRate overrides the rate).
//
// Frames and ground truth: as for the other camera datasets, the base frame is at cam0 with ROS
// body axes (x forward, y left, z up): the stereo model's local transform is
// CameraModel::opticalRotation(), the scan's is base -> velodyne = opticalRotation() * Tr.
// The poses' world is itself an optical frame (cam0 at frame 0), so it is re-expressed with ROS
// axes too, becoming the base frame at frame 0 (x forward, z up, as the car starts level):
//     groundTruth = opticalRotation() * pose(row n) * opticalRotation()^-1
// i.e. frame 0's ground truth is the identity, as a SLAM run's first pose, and a car driving
// forward moves along +x. Without calib.txt (scans only), the
// velodyne mounting is taken from the KITTI sensor setup drawing (Geiger et al., IJRR 2013):
// 0.27 m behind and 0.08 m above cam0, axes parallel to the base (logged as a warning); give
// the sequence's calib.txt through calibrationPath for the exact one.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "ReaderSupport.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/StereoCameraModel.h"

namespace rtabmap {
namespace {

using eval_detail::joinPath;
using eval_detail::throwAt;

constexpr double kVelodyneRangeMax = 120.0;

struct KittiCalib {
  std::map<std::string, std::vector<double>> matrices;  // "P0" -> 12 values, "Tr" -> 12
  bool has(const std::string& k) const { return matrices.count(k) > 0; }
};

KittiCalib readCalib(const std::string& path) {
  eval_detail::TextLineReader in(path);
  KittiCalib calib;
  std::string line;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    const size_t colon = line.find(':');
    if (colon == std::string::npos) throwAt(path, in.lineNumber(), "expected `NAME: 12 numbers`");
    std::string key = line.substr(0, colon);
    while (!key.empty() && key.back() == ' ') key.pop_back();
    const auto f = eval_detail::splitFields(std::string_view(line).substr(colon + 1));
    if (f.size() != 12) {
      throwAt(path, in.lineNumber(), key + ": expected 12 numbers (3x4 row-major), got " + std::to_string(f.size()));
    }
    std::vector<double> v;
    for (auto t : f) v.push_back(eval_detail::parseNumber(t, path, in.lineNumber(), key.c_str()));
    if (key == "Tr_velo_to_cam" || key == "Tr_velo_cam") key = "Tr";
    calib.matrices[key] = v;
  }
  return calib;
}

// Frame number of "000094.bin" / "000094.png"; -1 if the stem is not all digits.
long frameNumber(const std::string& name) {
  const size_t dot = name.find('.');
  if (dot == 0 || dot == std::string::npos) return -1;
  long n = 0;
  for (size_t i = 0; i < dot; ++i) {
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) return -1;
    n = n * 10 + (name[i] - '0');
    if (n > 100000000) return -1;
  }
  return n;
}

cv::Mat readVelodyne(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw FormatError(path + ": cannot open");
  std::fseek(f, 0, SEEK_END);
  const long size = std::ftell(f);
  std::fseek(f, 0, SEEK_SET);
  if (size < 0 || size % 16 != 0) {
    std::fclose(f);
    throw FormatError(path + ": size " + std::to_string(size) +
                      " bytes is not a multiple of 16 (float32 x y z intensity per point)");
  }
  const int n = static_cast<int>(size / 16);
  cv::Mat points(1, n, CV_32FC4);
  const size_t read = n > 0 ? std::fread(points.data, 16, static_cast<size_t>(n), f) : 0;
  std::fclose(f);
  if (read != static_cast<size_t>(n)) throw FormatError(path + ": read error");
  return n > 0 ? points : cv::Mat();
}

class KittiReader : public eval_detail::WindowedReader {
 public:
  KittiReader(const std::string& path, const DatasetReaderOptions& options)
      : WindowedReader(options), path_(path) {
    if (!eval_detail::isDirectory(path)) {
      throw FormatError("kitti: " + path + " is not a folder (expected a KITTI odometry sequence: "
                        "image_0/, image_1/, velodyne/, calib.txt, times.txt)");
    }
    const std::string calibPath = !options.calibrationPath.empty() ? options.calibrationPath : joinPath(path, "calib.txt");
    const bool haveCalib = eval_detail::isFile(calibPath);
    KittiCalib calib;
    if (haveCalib) calib = readCalib(calibPath);

    imageDir0_ = joinPath(path, "image_0");
    imageDir1_ = joinPath(path, "image_1");
    haveImages_ = eval_detail::isDirectory(imageDir0_) && eval_detail::isDirectory(imageDir1_);
    velodyneDir_ = eval_detail::isDirectory(joinPath(path, "velodyne")) ? joinPath(path, "velodyne") : path;

    std::set<long> numbers;
    std::vector<double> times;
    const std::string timesPath = joinPath(path, "times.txt");
    if (eval_detail::isFile(timesPath)) {
      eval_detail::TextLineReader in(timesPath);
      std::string line;
      while (in.next(line)) {
        if (eval_detail::isCommentOrBlank(line)) continue;
        const auto f = eval_detail::splitFields(line);
        if (f.size() != 1) throwAt(timesPath, in.lineNumber(), "expected one stamp per line");
        times.push_back(eval_detail::parseNumber(f[0], timesPath, in.lineNumber(), "time"));
      }
      for (long i = 0; i < static_cast<long>(times.size()); ++i) numbers.insert(i);
    } else {
      if (haveImages_) {
        for (const auto& name : eval_detail::listFiles(imageDir0_, {".png"})) {
          if (frameNumber(name) >= 0) numbers.insert(frameNumber(name));
        }
      }
      for (const auto& name : eval_detail::listFiles(velodyneDir_, {".bin"})) {
        if (frameNumber(name) >= 0) numbers.insert(frameNumber(name));
      }
    }
    if (numbers.empty()) {
      throw FormatError("kitti: " + path + ": no frame (no times.txt, image_0/NNNNNN.png or "
                        "NNNNNN.bin velodyne scan)");
    }
    numbers_.assign(numbers.begin(), numbers.end());
    rate_ = options.frameRate > 0.0 ? options.frameRate : 10.0;
    for (long n : numbers_) {
      stamps_.push_back(n < static_cast<long>(times.size()) ? times[static_cast<size_t>(n)]
                                                            : static_cast<double>(n) / rate_);
    }

    if (haveImages_ && options.images) {
      if (!calib.has("P0") || !calib.has("P1")) {
        throw FormatError("kitti: " + path + ": the stereo images need calib.txt with P0 and P1" +
                          (haveCalib ? " (" + calibPath + " lacks them)" : ""));
      }
      const auto& p0 = calib.matrices["P0"];
      const auto& p1 = calib.matrices["P1"];
      if (p0[0] <= 0.0 || p1[0] <= 0.0 || p1[3] >= 0.0) {
        throw FormatError(calibPath + ": P0/P1 do not describe a rectified pair (fx > 0, P1 Tx < 0)");
      }
      const double baseline = -p1[3] / p1[0];
      stereo_ = StereoCameraModel(p0[0], p0[5], p0[2], p0[6], baseline, CameraModel::opticalRotation());
    }

    if (calib.has("Tr")) {
      velodyneTransform_ = CameraModel::opticalRotation() * Transform::fromArray12(calib.matrices["Tr"].data());
    } else {
      velodyneTransform_ = Transform(-0.27, 0.0, 0.08, 0.0, 0.0, 0.0);
      if (options.scans) {
        RTABMAP_WARN("kitti: " << path << ": no calib.txt with Tr: velodyne mounting assumed 0.27 m "
                               << "behind and 0.08 m above cam0 (KITTI setup drawing); give calib.txt "
                               << "for the exact transform");
      }
    }

    std::string gt = options.groundTruthPath;
    if (gt.empty()) gt = findPoses(path);
    if (!gt.empty()) poses_ = eval_detail::readPoseRows(gt);
  }

  std::string format() const override { return "kitti"; }
  int frameCount() const override { return windowed(static_cast<int>(numbers_.size())); }

 protected:
  bool readNext(DatasetRecord& record) override {
    if (cursor_ >= numbers_.size()) return false;
    const size_t i = cursor_++;
    const long n = numbers_[i];
    record = DatasetRecord();
    record.kind = DatasetRecord::Kind::kFrame;
    record.stamp = stamps_[i];
    if (nextFrameSkipped()) return true;
    char name[32];
    std::snprintf(name, sizeof(name), "%06ld", n);
    const std::string stem(name);
    SensorData data;
    if (haveImages_ && options().images) {
      const cv::Mat left = eval_detail::readImage(joinPath(imageDir0_, stem + ".png"), cv::IMREAD_GRAYSCALE);
      const cv::Mat right = eval_detail::readImage(joinPath(imageDir1_, stem + ".png"), cv::IMREAD_GRAYSCALE);
      StereoCameraModel model = stereo_;
      if (model.left().imageSize() != left.size()) {
        model = StereoCameraModel(stereo_.left().fx(), stereo_.left().fy(), stereo_.left().cx(),
                                  stereo_.left().cy(), stereo_.baseline(), stereo_.localTransform(),
                                  left.size());
        stereo_ = model;
      }
      data = SensorData(left, right, model);
    }
    if (options().scans) {
      const std::string bin = joinPath(velodyneDir_, stem + ".bin");
      if (eval_detail::isFile(bin)) {
        const cv::Mat points = readVelodyne(bin);
        data.setLaserScan(LaserScan(points, points.cols, 0.0, kVelodyneRangeMax, LaserScan::kXYZI,
                                    velodyneTransform_));
      }
    }
    data.setId(static_cast<int>(n) + 1);
    data.setStamp(record.stamp);
    if (n < static_cast<long>(poses_.size())) {
      const Transform optical = CameraModel::opticalRotation();
      data.setGroundTruth(optical * poses_[static_cast<size_t>(n)] * optical.inverse());
    }
    record.data = std::move(data);
    return true;
  }

 private:
  static std::string findPoses(const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path p = fs::path(path).lexically_normal();
    std::string seq = p.filename().string();
    if (seq.empty()) seq = p.parent_path().filename().string();
    const std::string standard = (fs::path(path) / ".." / ".." / "poses" / (seq + ".txt")).string();
    if (eval_detail::isFile(standard)) return standard;
    if (eval_detail::isFile(joinPath(path, "poses.txt"))) return joinPath(path, "poses.txt");
    for (const auto& name : eval_detail::listFiles(path, {".txt", ".csv"})) {
      if (eval_detail::toLower(name).find("pose") != std::string::npos) return joinPath(path, name);
    }
    return "";
  }

  std::string path_;
  std::string imageDir0_, imageDir1_, velodyneDir_;
  bool haveImages_ = false;
  std::vector<long> numbers_;
  std::vector<double> stamps_;
  double rate_ = 10.0;
  StereoCameraModel stereo_;
  Transform velodyneTransform_ = Transform::Identity();
  std::vector<Transform> poses_;
  size_t cursor_ = 0;
};

[[maybe_unused]] const bool kRegistered = registerDatasetFormat(
    "kitti", [](const std::string& path, const DatasetReaderOptions& options) {
      return std::unique_ptr<DatasetReader>(new KittiReader(path, options));
    });

}  // namespace
}  // namespace rtabmap

#include "rtabmap_core/sim/SimDatasetReader.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/sim/SimDatasetWriter.h"

namespace fs = std::filesystem;

namespace rtabmap::sim {

namespace {

std::string framePath(const std::string& dir, const std::string& folder, int index, const std::string& ext) {
  return dir + "/" + simFramePath(folder, index, ext);
}

// x y z qx qy qz qw starting at v[first].
Transform poseFrom(const std::vector<double>& v, size_t first) {
  return Transform(v[first], v[first + 1], v[first + 2], v[first + 3], v[first + 4], v[first + 5], v[first + 6]);
}

// The planar covariance (upper triangle of x, y, yaw) as a 6x6 over x y z roll pitch yaw.
Eigen::Matrix<double, 6, 6> covariance6(const std::vector<double>& v, size_t first) {
  Eigen::Matrix<double, 6, 6> m = Eigen::Matrix<double, 6, 6>::Zero();
  m(0, 0) = std::max(v[first], 1e-9);
  m(0, 1) = m(1, 0) = v[first + 1];
  m(0, 5) = m(5, 0) = v[first + 2];
  m(1, 1) = std::max(v[first + 3], 1e-9);
  m(1, 5) = m(5, 1) = v[first + 4];
  m(5, 5) = std::max(v[first + 5], 1e-9);
  m(2, 2) = m(3, 3) = m(4, 4) = 1e-6;
  return m;
}

std::vector<char> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FormatError(path + ": cannot open");
  return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

cv::Mat readImage(const std::string& path, int type) {
  cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw FormatError(path + ": missing or not an image");
  if (image.type() != type) throw FormatError(path + ": unexpected image type (rewritten by another tool?)");
  return image;
}

bool truthy(const std::string& v) { return v == "1" || v == "true" || v == "yes"; }

}  // namespace

// Numbers of the data lines of a text table, one line at a time.
class SimDatasetReader::LineSource {
 public:
  LineSource(const std::string& path, size_t fields) : path_(path), fields_(fields), in_(path) {
    if (!in_) throw FormatError(path + ": cannot open (not a complete sim dataset?)");
  }
  bool next(std::vector<double>& values) {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_;
      const size_t start = line.find_first_not_of(" \t\r");
      if (start == std::string::npos || line[start] == '#') continue;
      values.clear();
      const char* p = line.c_str() + start;
      while (*p) {
        char* end = nullptr;
        errno = 0;
        const double v = std::strtod(p, &end);
        if (end == p) throw FormatError(path_ + ":" + std::to_string(line_) + ": not a number near \"" + std::string(p).substr(0, 16) + "\"");
        values.push_back(v);
        p = end;
        while (*p == ' ' || *p == '\t' || *p == '\r') ++p;
      }
      if (values.size() != fields_) {
        throw FormatError(path_ + ":" + std::to_string(line_) + ": expected " + std::to_string(fields_) + " numbers, got " +
                          std::to_string(values.size()));
      }
      return true;
    }
    return false;
  }
  const std::string& path() const { return path_; }
  long line() const { return line_; }

 private:
  std::string path_;
  size_t fields_;
  std::ifstream in_;
  long line_ = 0;
};

std::string parseSimReaderQuery(const std::string& pathWithQuery, SimReaderOptions& options) {
  const size_t q = pathWithQuery.find('?');
  if (q == std::string::npos) return pathWithQuery;
  const std::string query = pathWithQuery.substr(q + 1);
  size_t pos = 0;
  while (pos <= query.size()) {
    const size_t amp = query.find('&', pos);
    const std::string item = query.substr(pos, amp == std::string::npos ? std::string::npos : amp - pos);
    pos = amp == std::string::npos ? query.size() + 1 : amp + 1;
    if (item.empty()) continue;
    const size_t eq = item.find('=');
    const std::string key = item.substr(0, eq);
    const std::string value = eq == std::string::npos ? "" : item.substr(eq + 1);
    if (key == "camera") {
      if (value == "rgbd") options.camera = SimReaderOptions::Camera::kRgbd;
      else if (value == "stereo") options.camera = SimReaderOptions::Camera::kStereo;
      else if (value == "none") options.camera = SimReaderOptions::Camera::kNone;
      else throw FormatError("sim dataset: camera=" + value + " (expected rgbd, stereo or none)");
    } else if (key == "scan") {
      if (value == "urg") options.scan = SimReaderOptions::Scan::kUrg;
      else if (value == "utm") options.scan = SimReaderOptions::Scan::kUtm;
      else if (value == "lidar") options.scan = SimReaderOptions::Scan::kLidar;
      else if (value == "none") options.scan = SimReaderOptions::Scan::kNone;
      else throw FormatError("sim dataset: scan=" + value + " (expected urg, utm, lidar or none)");
    } else if (key == "depth32") {
      options.depth32 = truthy(value);
    } else {
      throw FormatError("sim dataset: unknown option \"" + key + "\" after '?' (expected camera, scan, depth32)");
    }
  }
  return pathWithQuery.substr(0, q);
}

SimDatasetReader::SimDatasetReader(const std::string& dir, const DatasetReaderOptions& options,
                                   const SimReaderOptions& simOptions)
    : dir_(dir), options_(options), simOptions_(simOptions) {
  if (options.startFrame < 0 || options.maxFrames < 0) throw FormatError("sim dataset: startFrame and maxFrames must be >= 0");
  readInfo();
  readTables();
  const int total = totalFrames();
  nextFrame_ = std::min(options.startFrame, total);
  lastFrame_ = options.maxFrames > 0 ? std::min(total, nextFrame_ + options.maxFrames) : total;
  if (nextFrame_ > 0) skipUntil_ = frames_[static_cast<size_t>(nextFrame_ - 1)].stamp;
  if (options.imu) imu_ = std::make_unique<LineSource>(dir_ + "/imu.txt", 7);
  if (options.odometry) {
    odometry_ = std::make_unique<LineSource>(dir_ + "/odometry.txt", 8);
    twist_ = std::make_unique<LineSource>(dir_ + "/odometry_twist.txt", 9);
  }
}

SimDatasetReader::~SimDatasetReader() = default;

void SimDatasetReader::readInfo() {
  const std::string path = dir_ + "/info.yaml";
  if (!fs::is_directory(dir_)) throw FormatError("sim dataset: " + dir_ + " is not a folder");
  YAML::Node info;
  try {
    info = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw FormatError("sim dataset: " + path + " is missing (expected a folder written by rtabmap-sim)");
  } catch (const YAML::Exception& e) {
    throw FormatError("sim dataset: " + path + ": " + e.what());
  }
  try {
    const std::string format = info["format"] ? info["format"].as<std::string>() : "";
    if (format == std::string(kSimDatasetFormat) + "_sessions") {
      std::string sessions;
      for (const auto& s : info["sessions"]) sessions += (sessions.empty() ? "" : ", ") + dir_ + "/" + s.as<std::string>();
      throw FormatError("sim dataset: " + dir_ + " holds a multi-session scenario; open one of its sessions: " + sessions);
    }
    if (format != kSimDatasetFormat) throw FormatError("sim dataset: " + path + " is not a " + kSimDatasetFormat + " info file");
    const int version = info["format_version"].as<int>();
    if (version > kSimDatasetFormatVersion) {
      throw FormatError("sim dataset: " + path + " has format version " + std::to_string(version) + "; this reader knows up to " +
                        std::to_string(kSimDatasetFormatVersion));
    }
    meta_.simulatorVersion = info["simulator_version"].as<std::string>();
    meta_.scenario = info["scenario"].as<std::string>();
    meta_.session = info["session"].as<std::string>();
    meta_.seed = info["seed"].as<unsigned long long>();
    meta_.frames = info["frames"].as<int>();
    meta_.duration = info["duration_s"].as<double>();
    meta_.distance = info["distance_m"].as<double>();
    if (info["options"]) {
      for (const auto& kv : info["options"]) meta_.options[kv.first.as<std::string>()] = kv.second.as<std::string>();
    }
    const YAML::Node sensors = info["sensors"];
    meta_.rgb = static_cast<bool>(sensors["rgb"]);
    meta_.depth32 = static_cast<bool>(sensors["depth32"]);
    meta_.stereo = static_cast<bool>(sensors["stereo"]);
    meta_.urg = static_cast<bool>(sensors["scan_urg"]);
    meta_.utm = static_cast<bool>(sensors["scan_utm"]);
    meta_.lidar = static_cast<bool>(sensors["lidar"]);
    for (const char* key : {"scan_urg", "scan_utm", "lidar"}) {
      if (!sensors[key]) continue;
      for (const auto& kv : sensors[key]) {
        if (kv.second.IsScalar()) {
          try {
            laserSpecs_[key][kv.first.as<std::string>()] = kv.second.as<double>();
          } catch (const YAML::Exception&) {  // a name (folder, frame): not a number
          }
        }
      }
    }
    meta_.imuGyroVariance = sensors["imu"]["gyro_variance"].as<double>();
    meta_.imuAccelVariance = sensors["imu"]["accel_variance"].as<double>();
    const std::string camera = info["reader_defaults"]["camera"].as<std::string>();
    const std::string scan = info["reader_defaults"]["scan"].as<std::string>();
    camera_ = simOptions_.camera;
    if (camera_ == SimReaderOptions::Camera::kDefault) {
      camera_ = camera == "rgbd" ? SimReaderOptions::Camera::kRgbd
                : camera == "stereo" ? SimReaderOptions::Camera::kStereo : SimReaderOptions::Camera::kNone;
    }
    scan_ = simOptions_.scan;
    if (scan_ == SimReaderOptions::Scan::kDefault) {
      scan_ = scan == "urg" ? SimReaderOptions::Scan::kUrg
              : scan == "utm" ? SimReaderOptions::Scan::kUtm
              : scan == "lidar" ? SimReaderOptions::Scan::kLidar : SimReaderOptions::Scan::kNone;
    }
  } catch (const YAML::Exception& e) {
    throw FormatError("sim dataset: " + path + ": " + e.what() + " (written by an incompatible simulator?)");
  }
  auto missing = [&](const std::string& what, const std::string& flag) {
    throw FormatError("sim dataset: " + dir_ + " has no " + what + " (it was written with " + flag + ")");
  };
  if (camera_ == SimReaderOptions::Camera::kRgbd && !meta_.rgb) missing("RGB-D images", "--no-rgbd");
  if (camera_ == SimReaderOptions::Camera::kStereo && (!meta_.stereo || !meta_.rgb)) missing("stereo pair", "--no-stereo or --no-rgbd");
  if (simOptions_.depth32 && !meta_.depth32) missing("float depth (depth32/)", "no --depth32");
  if (scan_ == SimReaderOptions::Scan::kUrg && !meta_.urg) missing("URG scans", "--no-urg");
  if (scan_ == SimReaderOptions::Scan::kUtm && !meta_.utm) missing("UTM scans", "--no-utm");
  if (scan_ == SimReaderOptions::Scan::kLidar && !meta_.lidar) missing("lidar clouds", "no --lidar3d");
}

void SimDatasetReader::readTables() {
  {
    std::ifstream t(dir_ + "/transforms.txt");
    std::string line;
    long n = 0;
    while (std::getline(t, line)) {
      ++n;
      if (line.empty() || line[0] == '#') continue;
      std::istringstream fields(line);
      std::string parent, child;
      double v[7];
      fields >> parent >> child;
      for (double& x : v) fields >> x;
      if (!fields) throw FormatError(dir_ + "/transforms.txt:" + std::to_string(n) + ": expected `parent child x y z qx qy qz qw`");
      transforms_[child] = Transform(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
    }
  }
  if (meta_.rgb || meta_.stereo) rgbModel_ = CameraModel::load(dir_ + "/calib/rgb.yaml");
  if (meta_.stereo) {
    stereoModel_ = StereoCameraModel("stereo", CameraModel::load(dir_ + "/calib/left.yaml"), CameraModel::load(dir_ + "/calib/right.yaml"));
  }
  LineSource frames(dir_ + "/frames.txt", 15);
  LineSource truth(dir_ + "/groundtruth.txt", 8);
  std::vector<double> f, g;
  while (frames.next(f)) {
    if (!truth.next(g)) throw FormatError(truth.path() + ": fewer lines than frames.txt");
    if (std::fabs(f[1] - g[0]) > 1e-6) {
      throw FormatError(truth.path() + ":" + std::to_string(truth.line()) + ": stamp differs from frames.txt line " +
                        std::to_string(frames.line()));
    }
    FrameRow row;
    row.index = static_cast<int>(f[0]);
    row.stamp = f[1];
    row.odometry = poseFrom(f, 2);
    row.covariance = covariance6(f, 9);
    row.groundTruth = poseFrom(g, 1);
    if (row.index != static_cast<int>(frames_.size())) {
      throw FormatError(frames.path() + ":" + std::to_string(frames.line()) + ": frame index " + std::to_string(row.index) +
                        " out of sequence");
    }
    frames_.push_back(row);
  }
  if (static_cast<int>(frames_.size()) != meta_.frames) {
    throw FormatError(dir_ + "/frames.txt: " + std::to_string(frames_.size()) + " frames, info.yaml says " +
                      std::to_string(meta_.frames) + " (an interrupted run?)");
  }
}

int SimDatasetReader::frameCount() const { return std::max(0, lastFrame_ - std::min(options_.startFrame, totalFrames())); }


LaserScan SimDatasetReader::readScan(const std::string& folder, int index, const std::string& frame) const {
  const std::string path = framePath(dir_, folder, index, ".bin");
  const std::vector<char> bytes = readBytes(path);
  const auto& spec = laserSpecs_.at(folder);
  const Transform& local = transforms_.count(frame) ? transforms_.at(frame) : Transform::Identity();
  if (folder == "lidar") {
    if (bytes.size() % (4 * sizeof(float)) != 0) throw FormatError(path + ": size is not a whole number of points");
    const int n = static_cast<int>(bytes.size() / (4 * sizeof(float)));
    cv::Mat data;
    if (n > 0) {
      data = cv::Mat(1, n, CV_32FC4);
      std::copy(bytes.begin(), bytes.end(), reinterpret_cast<char*>(data.data));
    }
    return LaserScan(data, static_cast<int>(spec.at("rings") * spec.at("azimuth_steps")), spec.at("range_min"), spec.at("range_max"),
                     LaserScan::kXYZI, local);
  }
  const int beams = static_cast<int>(spec.at("beams"));
  if (bytes.size() != 2 * sizeof(float) * static_cast<size_t>(beams)) {
    throw FormatError(path + ": expected " + std::to_string(beams) + " ranges and intensities (" +
                      std::to_string(2 * sizeof(float) * beams) + " bytes), got " + std::to_string(bytes.size()) + " bytes");
  }
  std::vector<float> ranges(static_cast<size_t>(beams)), intensities(static_cast<size_t>(beams));
  std::copy(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(beams * sizeof(float)), reinterpret_cast<char*>(ranges.data()));
  std::copy(bytes.begin() + static_cast<std::ptrdiff_t>(beams * sizeof(float)), bytes.end(), reinterpret_cast<char*>(intensities.data()));
  return LaserScan::fromRanges(ranges, spec.at("angle_min"), spec.at("angle_increment"), spec.at("range_min"), spec.at("range_max"),
                               local, intensities);
}

SimFrameRecord SimDatasetReader::readFrame(int index, bool images, bool scans) const {
  const FrameRow& row = frames_.at(static_cast<size_t>(index));
  SimFrameRecord r;
  r.index = row.index;
  r.stamp = row.stamp;
  r.odometry = row.odometry;
  r.odometryCovariance = row.covariance;
  r.groundTruth = row.groundTruth;
  if (images) {
    if (meta_.rgb) {
      r.rgb = readImage(framePath(dir_, "rgb", index, ".png"), CV_8UC3);
      r.depth = readImage(framePath(dir_, "depth", index, ".png"), CV_16UC1);
    }
    if (meta_.depth32) {
      const std::vector<char> b = readBytes(framePath(dir_, "depth32", index, ".bin"));
      r.depth32 = codec::uncompressData(reinterpret_cast<const unsigned char*>(b.data()), b.size());
    }
    if (meta_.stereo) r.right = readImage(framePath(dir_, "right", index, ".png"), CV_8UC1);
  }
  if (scans) {
    if (meta_.urg) r.urg = readScan("scan_urg", index, "laser_urg");
    if (meta_.utm) r.utm = readScan("scan_utm", index, "laser_utm");
    if (meta_.lidar) r.lidar = readScan("lidar", index, "lidar");
  }
  return r;
}

bool SimDatasetReader::peekAux(DatasetRecord& record, int& kind) {
  std::vector<double> v;
  if (imu_ && !haveImu_ && imu_->next(v)) {
    nextImu_ = DatasetRecord();
    nextImu_.kind = DatasetRecord::Kind::kImu;
    nextImu_.stamp = v[0];
    IMU imu;
    imu.angularVelocity = Eigen::Vector3d(v[1], v[2], v[3]);
    imu.linearAcceleration = Eigen::Vector3d(v[4], v[5], v[6]);
    imu.angularVelocityCovariance = Eigen::Matrix3d::Identity() * meta_.imuGyroVariance;
    imu.linearAccelerationCovariance = Eigen::Matrix3d::Identity() * meta_.imuAccelVariance;
    if (transforms_.count("imu_link")) imu.localTransform = transforms_.at("imu_link");
    nextImu_.data.setIMU(imu);
    nextImu_.data.setStamp(v[0]);
    haveImu_ = true;
  }
  if (odometry_ && !haveOdometry_ && odometry_->next(v)) {
    std::vector<double> t;
    if (!twist_->next(t) || std::fabs(t[0] - v[0]) > 1e-6) {
      throw FormatError(twist_->path() + ":" + std::to_string(twist_->line()) + ": does not match " + odometry_->path() + " line " +
                        std::to_string(odometry_->line()));
    }
    nextOdometry_ = DatasetRecord();
    nextOdometry_.kind = DatasetRecord::Kind::kOdometry;
    nextOdometry_.stamp = v[0];
    nextOdometry_.data.setOdom(poseFrom(v, 1), covariance6(t, 3));
    nextOdometry_.data.setStamp(v[0]);
    haveOdometry_ = true;
  }
  if (!haveImu_ && !haveOdometry_) return false;
  // IMU first at equal stamps, then odometry (the frame comes after both).
  if (haveImu_ && (!haveOdometry_ || nextImu_.stamp <= nextOdometry_.stamp)) {
    record = nextImu_;
    kind = 0;
  } else {
    record = nextOdometry_;
    kind = 1;
  }
  return true;
}

bool SimDatasetReader::next(DatasetRecord& record) {
  while (nextFrame_ < lastFrame_) {
    const FrameRow& row = frames_[static_cast<size_t>(nextFrame_)];
    DatasetRecord aux;
    int kind = -1;
    if (peekAux(aux, kind) && aux.stamp <= row.stamp) {
      (kind == 0 ? haveImu_ : haveOdometry_) = false;
      if (aux.stamp <= skipUntil_) continue;
      record = std::move(aux);
      return true;
    }
    const SimFrameRecord f = readFrame(nextFrame_, options_.images && camera_ != SimReaderOptions::Camera::kNone, false);
    const int id = nextFrame_ + 1;
    SensorData data;
    if (options_.images && camera_ == SimReaderOptions::Camera::kRgbd) {
      data = SensorData(f.rgb, simOptions_.depth32 ? f.depth32 : f.depth, rgbModel_, id, row.stamp);
    } else if (options_.images && camera_ == SimReaderOptions::Camera::kStereo) {
      cv::Mat left;
      cv::cvtColor(f.rgb, left, cv::COLOR_BGR2GRAY);
      data = SensorData(left, f.right, stereoModel_, id, row.stamp);
    }
    data.setId(id);
    data.setStamp(row.stamp);
    if (options_.scans) {
      if (scan_ == SimReaderOptions::Scan::kUrg) data.setLaserScan(readScan("scan_urg", nextFrame_, "laser_urg"));
      else if (scan_ == SimReaderOptions::Scan::kUtm) data.setLaserScan(readScan("scan_utm", nextFrame_, "laser_utm"));
      else if (scan_ == SimReaderOptions::Scan::kLidar) data.setLaserScan(readScan("lidar", nextFrame_, "lidar"));
    }
    data.setOdom(row.odometry, row.covariance);
    data.setGroundTruth(row.groundTruth);
    record = DatasetRecord();
    record.kind = DatasetRecord::Kind::kFrame;
    record.stamp = row.stamp;
    record.data = std::move(data);
    ++nextFrame_;
    return true;
  }
  return false;
}

std::unique_ptr<DatasetReader> openSimDataset(const std::string& path, const DatasetReaderOptions& options) {
  SimReaderOptions simOptions;
  const std::string dir = parseSimReaderQuery(path, simOptions);
  return std::make_unique<SimDatasetReader>(dir, options, simOptions);
}

namespace {
[[maybe_unused]] const bool kRegistered = registerDatasetFormat("sim", &openSimDataset);
}  // namespace

}  // namespace rtabmap::sim

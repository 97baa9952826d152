#include "rtabmap_core/sim/SimDatasetWriter.h"

#include <opencv2/imgproc.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/sim/PngWriter.h"

namespace fs = std::filesystem;

namespace rtabmap::sim {

namespace {


std::FILE* openText(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw Error("rtabmap-sim: cannot write " + path + ": " + std::strerror(errno));
  return f;
}

void writeBinary(const std::string& path, const void* data, size_t bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw Error("cannot write " + path + ": " + std::strerror(errno));
  const size_t written = bytes ? std::fwrite(data, 1, bytes, f) : 0;
  const bool ok = std::fclose(f) == 0 && written == bytes;
  if (!ok) throw Error("cannot write " + path + " (disk full?)");
}

// PNG through our own encoder (PngWriter.h): the dataset's largest cost, made cheaper.
void writeImage(const std::string& path, const cv::Mat& image) { writePng(path, image); }

// The float32 layout of a planar scan file: ranges then intensities (little-endian: the
// machines we run on are; static_assert below).
void writeScan(const std::string& path, const LaserReading& scan) {
  std::vector<float> data(scan.ranges);
  data.insert(data.end(), scan.intensities.begin(), scan.intensities.end());
  writeBinary(path, data.data(), data.size() * sizeof(float));
}

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "sim dataset binaries are little-endian");

void printPose(std::FILE* f, const Pose2& p) {
  std::fprintf(f, " %.9f %.9f %.9f %.9f %.9f %.9f %.9f", p.x, p.y, 0.0, 0.0, 0.0, std::sin(0.5 * p.yaw),
               std::cos(0.5 * p.yaw));
}

void printCovariance(std::FILE* f, const Eigen::Matrix3d& c) {
  std::fprintf(f, " %.9e %.9e %.9e %.9e %.9e %.9e", c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2));
}

void printTransform(std::FILE* f, const char* parent, const char* child, const Transform& t) {
  const Eigen::Quaterniond q = t.quaternion();
  std::fprintf(f, "%s %s %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", parent, child, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(),
               q.w());
}

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

std::string yamlQuoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string transformFields(const Transform& t) {
  return "x: " + number(t.x()) + ", y: " + number(t.y()) + ", z: " + number(t.z()) + ", yaw: " + number(t.yaw());
}

}  // namespace

std::string simFramePath(const std::string& folder, int index, const std::string& extension) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06d", index);
  return folder + "/" + name + extension;
}

SimDatasetWriter::SimDatasetWriter(const std::string& dir, const SimulationConfig& config, const SimDatasetInfo& info,
                                   int threads, bool writeDepth32)
    : dir_(dir), config_(config), info_(info), depth32_(writeDepth32 && config.colour) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_)) throw Error("rtabmap-sim: cannot create " + dir_ + ": " + ec.message());
  std::vector<std::string> folders = {"calib"};
  if (config.colour) folders.insert(folders.end(), {"rgb", "depth"});
  if (depth32_) folders.push_back("depth32");
  if (config.stereo) folders.push_back("right");
  if (config.scanUrg) folders.push_back("scan_urg");
  if (config.scanUtm) folders.push_back("scan_utm");
  if (config.lidar3d) folders.push_back("lidar");
  for (const auto& f : folders) {
    fs::create_directories(fs::path(dir_) / f, ec);
    if (ec) throw Error("rtabmap-sim: cannot create " + (fs::path(dir_) / f).string() + ": " + ec.message());
  }
  writeStatic();
  frames_ = openText(dir_ + "/frames.txt");
  std::fprintf(frames_, "# index stamp x y z qx qy qz qw cxx cxy cxw cyy cyw cww (odometry; covariance since the previous frame)\n");
  groundTruth_ = openText(dir_ + "/groundtruth.txt");
  std::fprintf(groundTruth_, "# timestamp tx ty tz qx qy qz qw (base_link in the world frame)\n");
  odometry_ = openText(dir_ + "/odometry.txt");
  std::fprintf(odometry_, "# timestamp tx ty tz qx qy qz qw (wheel odometry of base_link)\n");
  twist_ = openText(dir_ + "/odometry_twist.txt");
  std::fprintf(twist_, "# timestamp v w cxx cxy cxw cyy cyw cww (covariance since the previous sample)\n");
  imu_ = openText(dir_ + "/imu.txt");
  std::fprintf(imu_, "# timestamp wx wy wz ax ay az (imu_link)\n");
  for (int i = 0; i < std::max(1, threads); ++i) threads_.emplace_back([this] { worker(); });
}

SimDatasetWriter::~SimDatasetWriter() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  jobReady_.notify_all();
  for (auto& t : threads_) t.join();
  for (std::FILE* f : {frames_, groundTruth_, odometry_, twist_, imu_}) {
    if (f) std::fclose(f);
  }
}

void SimDatasetWriter::writeStatic() {
  const CameraSpec& cam = config_.camera;
  auto save = [&](const CameraModel& m, const std::string& name) {
    if (!m.save(dir_ + "/calib/" + name)) throw Error("rtabmap-sim: cannot write " + dir_ + "/calib/" + name);
  };
  if (config_.colour || config_.stereo) {
    save(cam.rgbModel(), "rgb.yaml");
    save(cam.leftModel(), "left.yaml");
  }
  if (config_.stereo) save(cam.rightModel(), "right.yaml");
  std::FILE* f = openText(dir_ + "/transforms.txt");
  std::fprintf(f, "# parent child x y z qx qy qz qw (static)\n");
  if (config_.colour || config_.stereo) printTransform(f, "base_link", "camera_rgb_optical_frame", cam.baseToOptical);
  if (config_.stereo) printTransform(f, "base_link", "camera_right_optical_frame", cam.baseToRightOptical());
  if (config_.scanUrg) printTransform(f, "base_link", "laser_urg", config_.urg.baseToLaser);
  if (config_.scanUtm) printTransform(f, "base_link", "laser_utm", config_.utm.baseToLaser);
  if (config_.lidar3d) printTransform(f, "base_link", "lidar", config_.lidar.baseToLidar);
  printTransform(f, "base_link", "imu_link", Transform(0.0, 0.0, 0.15, 0.0, 0.0, 0.0));
  if (std::fclose(f) != 0) throw Error("rtabmap-sim: cannot write " + dir_ + "/transforms.txt");
}

void SimDatasetWriter::onImu(const ImuSample& s) {
  std::fprintf(imu_, "%.6f %.9f %.9f %.9f %.9f %.9f %.9f\n", s.stamp, s.angularVelocity.x(), s.angularVelocity.y(),
               s.angularVelocity.z(), s.linearAcceleration.x(), s.linearAcceleration.y(), s.linearAcceleration.z());
}

void SimDatasetWriter::onOdometry(const OdometrySample& s) {
  std::fprintf(odometry_, "%.6f", s.stamp);
  printPose(odometry_, s.pose);
  std::fprintf(odometry_, "\n");
  std::fprintf(twist_, "%.6f %.9f %.9f", s.stamp, s.v, s.omega);
  printCovariance(twist_, s.covariance);
  std::fprintf(twist_, "\n");
}

void SimDatasetWriter::onFrame(SimFrame&& frame) {
  std::fprintf(frames_, "%d %.6f", frame.index, frame.stamp);
  printPose(frames_, frame.odometry);
  printCovariance(frames_, frame.odometryCovariance);
  std::fprintf(frames_, "\n");
  std::fprintf(groundTruth_, "%.6f", frame.stamp);
  printPose(groundTruth_, frame.groundTruth);
  std::fprintf(groundTruth_, "\n");

  // Images are encoded by the workers; the frame's data moves into the jobs.
  auto shared = std::make_shared<SimFrame>(std::move(frame));
  const int i = shared->index;
  const std::string d = dir_ + "/";
  if (config_.colour) {
    enqueue([shared, d, i] { writeImage(d + simFramePath("rgb", i, ".png"), shared->bgr); });
    const bool float32 = depth32_;
    enqueue([shared, d, i, float32] {
      cv::Mat mm;
      // Millimetres, rounded; beyond 65.534 m (or nothing): 0, the usual "no depth".
      shared->depth.convertTo(mm, CV_16UC1, 1000.0);
      mm.setTo(0, shared->depth > 65.534f);
      writeImage(d + simFramePath("depth", i, ".png"), mm);
      if (float32) {
        const Bytes bytes = codec::compressData(shared->depth);
        writeBinary(d + simFramePath("depth32", i, ".bin"), bytes.data(), bytes.size());
      }
    });
  }
  if (config_.stereo) enqueue([shared, d, i] { writeImage(d + simFramePath("right", i, ".png"), shared->right); });
  if (config_.scanUrg || config_.scanUtm || config_.lidar3d) {
    const bool urg = config_.scanUrg, utm = config_.scanUtm, lidar = config_.lidar3d;
    enqueue([shared, d, i, urg, utm, lidar] {
      if (urg) writeScan(d + simFramePath("scan_urg", i, ".bin"), shared->urg);
      if (utm) writeScan(d + simFramePath("scan_utm", i, ".bin"), shared->utm);
      if (lidar) {
        const cv::Mat& p = shared->lidar;
        writeBinary(d + simFramePath("lidar", i, ".bin"), p.empty() ? nullptr : p.data, p.empty() ? 0 : p.total() * p.elemSize());
      }
    });
  }
}

void SimDatasetWriter::enqueue(std::function<void()> job) {
  std::unique_lock<std::mutex> lock(mutex_);
  // Bounded: a few frames in flight at most, so memory stays flat on long runs.
  jobDone_.wait(lock, [&] { return jobs_.size() < 4 * threads_.size() + 4; });
  jobs_.push_back(std::move(job));
  jobReady_.notify_one();
}

void SimDatasetWriter::worker() {
  while (true) {
    std::function<void()> job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      jobReady_.wait(lock, [&] { return stopping_ || !jobs_.empty(); });
      if (jobs_.empty()) return;
      job = std::move(jobs_.front());
      jobs_.pop_front();
      ++running_;
    }
    std::string error;
    try {
      job();
    } catch (const std::exception& e) {
      error = e.what();
    }
    {
      std::unique_lock<std::mutex> lock(mutex_);
      --running_;
      if (!error.empty() && firstError_.empty()) firstError_ = error;
    }
    jobDone_.notify_all();
  }
}

void SimDatasetWriter::finish(const SessionSummary& summary) {
  if (finished_) return;
  finished_ = true;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    jobDone_.wait(lock, [&] { return jobs_.empty() && running_ == 0; });
    if (!firstError_.empty()) throw Error("rtabmap-sim: " + firstError_);
  }
  for (std::FILE** f : {&frames_, &groundTruth_, &odometry_, &twist_, &imu_}) {
    const bool ok = std::fclose(*f) == 0;
    *f = nullptr;
    if (!ok) throw Error("rtabmap-sim: cannot finish the text files in " + dir_ + " (disk full?)");
  }

  const SimulationConfig& c = config_;
  std::string y;
  y += "# A dataset written by rtabmap-sim (layout: rtabmap_core/sim/SimDatasetWriter.h).\n";
  y += std::string("format: ") + kSimDatasetFormat + "\n";
  y += "format_version: " + std::to_string(kSimDatasetFormatVersion) + "\n";
  y += "simulator: rtabmap-sim\n";
  y += std::string("simulator_version: ") + kSimulatorVersion + "\n";
  y += "scenario: " + yamlQuoted(info_.scenario) + "\n";
  y += "session: " + yamlQuoted(info_.session) + "\n";
  y += "seed: " + std::to_string(info_.seed) + "\n";
  y += "frames: " + std::to_string(summary.frames) + "\n";
  y += "imu_samples: " + std::to_string(summary.imuSamples) + "\n";
  y += "odometry_samples: " + std::to_string(summary.odometrySamples) + "\n";
  y += "duration_s: " + number(summary.duration) + "\n";
  y += "distance_m: " + number(summary.distance) + "\n";
  y += "start_stamp: " + number(c.startStamp) + "\n";
  y += "frame_rate: " + number(c.frameRate) + "\n";
  y += "options:\n";
  for (const auto& [key, value] : info_.options) y += "  " + key + ": " + yamlQuoted(value) + "\n";
  y += "sensors:\n";
  const CameraIntrinsics& K = c.camera.intrinsics;
  if (c.colour) {
    y += "  rgb: {folder: rgb, calibration: calib/rgb.yaml, frame: camera_rgb_optical_frame, width: " + std::to_string(K.width) +
         ", height: " + std::to_string(K.height) + "}\n";
    y += "  depth: {folder: depth, encoding: 16UC1, unit: mm, registered_to: rgb}\n";
    if (depth32_) y += "  depth32: {folder: depth32, encoding: 32FC1, unit: m, container: rtabmap_compressed_data}\n";
  }
  if (c.stereo) {
    y += "  stereo: {left: rgb_as_grey, right_folder: right, calibration_left: calib/left.yaml, calibration_right: "
         "calib/right.yaml, baseline: " + number(c.camera.baseline) + ", frame_right: camera_right_optical_frame}\n";
  }
  auto laser = [&](const char* key, const LaserSpec& s) {
    y += std::string("  ") + key + ": {folder: " + key + ", frame: laser_" + s.name + ", beams: " + std::to_string(s.beams) +
         ", angle_min: " + number(s.angleMin) + ", angle_increment: " + number(s.angleIncrement) + ", range_min: " +
         number(s.rangeMin) + ", range_max: " + number(s.rangeMax) + ", noise_sigma: " + number(s.noiseSigma) + ", " +
         transformFields(s.baseToLaser) + "}\n";
  };
  if (c.scanUrg) laser("scan_urg", c.urg);
  if (c.scanUtm) laser("scan_utm", c.utm);
  if (c.lidar3d) {
    y += "  lidar: {folder: lidar, frame: lidar, rings: " + std::to_string(c.lidar.rings) + ", azimuth_steps: " +
         std::to_string(c.lidar.azimuthSteps) + ", elevation_min: " + number(c.lidar.elevationMin) + ", elevation_max: " +
         number(c.lidar.elevationMax) + ", range_min: " + number(c.lidar.rangeMin) + ", range_max: " + number(c.lidar.rangeMax) +
         ", " + transformFields(c.lidar.baseToLidar) + "}\n";
  }
  const ImuNoise& in = c.imuNoise;
  y += "  imu: {file: imu.txt, frame: imu_link, rate: " + number(c.imuRate) + ", gyro_noise_density: " + number(in.gyroNoiseDensity) +
       ", accel_noise_density: " + number(in.accelNoiseDensity) + ", gyro_bias_walk: " + number(in.gyroBiasWalk) +
       ", accel_bias_walk: " + number(in.accelBiasWalk) + ", gyro_variance: " +
       number(in.gyroNoiseDensity * in.gyroNoiseDensity * c.imuRate) + ", accel_variance: " +
       number(in.accelNoiseDensity * in.accelNoiseDensity * c.imuRate) + "}\n";
  const OdometryNoise& on = c.odometryNoise;
  y += "  odometry: {file: odometry.txt, twist_file: odometry_twist.txt, rate: " + number(c.odomRate) + ", translation_noise: " +
       number(on.translation) + ", rotation_noise: " + number(on.rotation) + ", rotation_per_metre_noise: " +
       number(on.rotationPerMetre) + ", scale_bias: " + number(on.scaleBias) + ", yaw_bias_per_metre: " + number(on.yawBiasPerMetre) +
       "}\n";
  // What the "sim" reader yields when not told otherwise.
  const std::string camera = c.colour ? "rgbd" : (c.stereo ? "stereo" : "none");
  const std::string scan = c.scanUrg ? "urg" : (c.scanUtm ? "utm" : (c.lidar3d ? "lidar" : "none"));
  y += "reader_defaults: {camera: " + camera + ", scan: " + scan + "}\n";
  std::FILE* f = openText(dir_ + "/info.yaml");
  const bool ok = std::fwrite(y.data(), 1, y.size(), f) == y.size();
  if (std::fclose(f) != 0 || !ok) throw Error("rtabmap-sim: cannot write " + dir_ + "/info.yaml");
}

void writeSimScenarioInfo(const std::string& dir, const SimDatasetInfo& info, const std::vector<std::string>& sessions) {
  std::string y;
  y += "# A multi-session scenario written by rtabmap-sim: each session is a \"sim\" dataset folder.\n";
  y += std::string("format: ") + kSimDatasetFormat + "_sessions\n";
  y += "format_version: " + std::to_string(kSimDatasetFormatVersion) + "\n";
  y += std::string("simulator_version: ") + kSimulatorVersion + "\n";
  y += "scenario: " + yamlQuoted(info.scenario) + "\n";
  y += "seed: " + std::to_string(info.seed) + "\n";
  y += "sessions:\n";
  for (const auto& s : sessions) y += "  - " + yamlQuoted(s) + "\n";
  y += "options:\n";
  for (const auto& [key, value] : info.options) y += "  " + key + ": " + yamlQuoted(value) + "\n";
  std::FILE* f = openText(dir + "/info.yaml");
  const bool ok = std::fwrite(y.data(), 1, y.size(), f) == y.size();
  if (std::fclose(f) != 0 || !ok) throw Error("rtabmap-sim: cannot write " + dir + "/info.yaml");
}

}  // namespace rtabmap::sim

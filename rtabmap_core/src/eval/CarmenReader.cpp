// "carmen": CARMEN log files (.clf, plain or bzip2-compressed), as the Radish / Freiburg SLAM
// evaluation datasets (Intel Research Lab, ACES, ...) are distributed.
//
// One message per line: `NAME [contents] ipc_timestamp ipc_hostname logger_timestamp`.
//  - FLASER num_readings [ranges] x y theta odom_x odom_y odom_theta ...: a front-laser frame.
//    The record's stamp is the ipc timestamp (the field before the host name): the stamps the
//    Freiburg relations files reference. The scan is planar, in the laser frame, with the
//    odometry pose (odom_x odom_y odom_theta) as data.odomPose(). FLASER carries no angles:
//    the SICK LMS logs these come from cover 180 degrees from -90 degrees (right) counter-
//    clockwise, so 180/181 beams are 1 degree apart (-90..+89 / -90..+90), 360/361 beams 0.5
//    degree; another count n spreads 180 degrees over n - 1 intervals. The laser sits at the
//    robot's origin unless PARAM robot_frontlaser_offset (metres forward) says otherwise. The
//    x y theta fields (the laser pose, equal to the odometry in raw logs, a corrected pose in
//    others) are not used.
//  - ROBOTLASER1 (newer logs): start angle, field of view, resolution and maximum range come
//    from the message; the laser's mounting from its laser and robot poses (robot^-1 * laser);
//    remissions become intensities when there is one per beam.
//  - ODOM x y theta tv rv accel ...: a kOdometry record (pose only; velocities are dropped).
//  - PARAM name value: read for the laser offset and maximum range; other messages (SYNC,
//    RLASER, TRUEPOS, RAWLASER*, NMEA-*, ...) are skipped.
// Odometry covariance: the logs carry none; records get SensorData's identity ("unknown").
//
// No-returns. A reading at or beyond the sensor's maximum range is a no-return and is dropped
// (LaserScan keeps maxPoints = the beam count). The maximum range is, in order:
// DatasetReaderOptions::scanRangeMax; a PARAM naming a front laser max range
// (robot_front_laser_max, laser_front_laser_max_range, ...); else the data decide, in a first
// pass over the file: when the largest reading of the log repeats (at least 10 times), it is
// the sensor's saturation value and the maximum range becomes min(it, 80 m); otherwise 80 m
// (the SICK LMS's long-range mode). On the shipped logs: ACES saturates at 50.00 m (11,139
// readings: range max 50 m), Intel at 81.83 m (68,313 readings: range max 80 m).
//
// Time order. Stamps in a log are not always monotonic: in Intel, scans and odometry arrive
// up to 0.9 s late. Records pass through a 5-second reordering buffer (stable for equal
// stamps), so the stream is time-ordered for every log whose disorder stays within it; a later
// record is still yielded, with one warning.
#include <cmath>
#include <limits>
#include <memory>
#include <queue>
#include <string>
#include <vector>

#include "ReaderSupport.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/geometry/LaserScan.h"

namespace rtabmap {
namespace {

using eval_detail::parseInteger;
using eval_detail::parseNumber;
using eval_detail::splitFields;
using eval_detail::TextLineReader;
using eval_detail::throwAt;

constexpr double kDefaultRangeMax = 80.0;
constexpr double kReorderWindow = 5.0;     // seconds
constexpr size_t kMaxBuffered = 200000;    // records, whatever their stamps
constexpr int kMinSaturationCount = 10;

bool isLaserMaxRangeParam(const std::string& name) {
  return name == "robot_front_laser_max" || name == "robot_frontlaser_max" ||
         name == "laser_front_laser_max_range" || name == "laser_laser1_max_range" ||
         name == "robot_front_laser_max_range";
}

bool isFrontOffsetParam(const std::string& name) {
  return name == "robot_frontlaser_offset" || name == "robot_front_laser_offset";
}

void flaserAngles(size_t n, double& angleMin, double& increment) {
  angleMin = -M_PI / 2.0;
  if (n == 180 || n == 181) {
    increment = M_PI / 180.0;
  } else if (n == 360 || n == 361) {
    increment = M_PI / 360.0;
  } else {
    increment = n > 1 ? M_PI / static_cast<double>(n - 1) : 0.0;
  }
}

struct Survey {
  double paramRangeMax = 0.0;
  std::string paramName;
  double maxReading = 0.0;
  long long countAtMax = 0;
  int frames = 0;
};

// First pass: the maximum-range PARAM, the saturation value of FLASER readings, the number of
// frames. Lenient: malformed lines are left to the main pass, which reports them in order.
Survey survey(const std::string& path) {
  Survey s;
  TextLineReader in(path);
  std::string line;
  while (in.next(line)) {
    if (line.size() < 4) continue;
    if (line.compare(0, 7, "FLASER ") == 0) {
      const auto f = splitFields(line);
      long long n = 0;
      if (f.size() < 2 || !eval_detail::tryParseInteger(f[1], n) || n < 0 ||
          f.size() < static_cast<size_t>(n) + 10) {
        continue;
      }
      ++s.frames;
      for (long long i = 0; i < n; ++i) {
        double r = 0.0;
        if (!eval_detail::tryParseNumber(f[2 + i], r)) continue;
        if (r > s.maxReading + 0.005) {
          s.maxReading = r;
          s.countAtMax = 1;
        } else if (r >= s.maxReading - 0.005) {
          ++s.countAtMax;
        }
      }
    } else if (line.compare(0, 12, "ROBOTLASER1 ") == 0) {
      ++s.frames;
    } else if (line.compare(0, 6, "PARAM ") == 0) {
      const auto f = splitFields(line);
      double v = 0.0;
      if (f.size() >= 3 && isLaserMaxRangeParam(std::string(f[1])) &&
          eval_detail::tryParseNumber(f[2], v) && v > 0.0) {
        s.paramRangeMax = v;
        s.paramName = std::string(f[1]);
      }
    }
  }
  return s;
}

struct Buffered {
  DatasetRecord record;
  long seq = 0;
};

struct Later {
  bool operator()(const Buffered& a, const Buffered& b) const {
    if (a.record.stamp != b.record.stamp) return a.record.stamp > b.record.stamp;
    return a.seq > b.seq;
  }
};

class CarmenReader : public eval_detail::WindowedReader {
 public:
  CarmenReader(const std::string& path, const DatasetReaderOptions& options)
      : WindowedReader(options), path_(path) {
    if (options.scanRangeMax > 0.0) {
      rangeMax_ = options.scanRangeMax;
      rangeMaxFixed_ = true;
    } else {
      const Survey s = survey(path);
      frames_ = s.frames;
      if (s.paramRangeMax > 0.0) {
        rangeMax_ = s.paramRangeMax;
        rangeMaxFixed_ = true;
        RTABMAP_INFO(path << ": laser range max " << rangeMax_ << " m (PARAM " << s.paramName << ")");
      } else if (s.countAtMax >= kMinSaturationCount && s.maxReading > 1.0) {
        rangeMax_ = std::min(s.maxReading, kDefaultRangeMax);
        RTABMAP_INFO(path << ": readings of " << s.maxReading << " m (" << s.countAtMax
                          << " of them) are the laser's no-return value: range max " << rangeMax_
                          << " m");
      } else {
        rangeMax_ = kDefaultRangeMax;
        RTABMAP_INFO(path << ": no saturation value in the readings: range max " << rangeMax_ << " m");
      }
    }
    in_ = std::make_unique<TextLineReader>(path);
  }

  std::string format() const override { return "carmen"; }
  int frameCount() const override { return frames_ < 0 ? -1 : windowed(frames_); }

 protected:
  bool readNext(DatasetRecord& record) override {
    // Read on until the oldest buffered record is older than anything still to come could be.
    while (!eof_ && heap_.size() < kMaxBuffered &&
           (heap_.empty() || heap_.top().record.stamp > latestStamp_ - kReorderWindow)) {
      if (!readLine()) eof_ = true;
    }
    if (heap_.empty()) return false;
    record = heap_.top().record;  // priority_queue::top is const: copy (cv::Mat shares data)
    heap_.pop();
    if (record.stamp < lastEmitted_) {
      if (!warnedDisorder_) {
        RTABMAP_WARN(path_ << ": a record stamped " << record.stamp << " comes "
                           << (lastEmitted_ - record.stamp)
                           << " s after a later one, beyond the reordering window; the stream is "
                              "not strictly time-ordered");
        warnedDisorder_ = true;
      }
    } else {
      lastEmitted_ = record.stamp;
    }
    if (record.kind == DatasetRecord::Kind::kFrame) record.data.setId(++frameId_);
    return true;
  }

 private:
  // Parses lines until one yields a record (pushed on the heap); false at the end of file.
  bool readLine() {
    std::string line;
    while (in_->next(line)) {
      if (eval_detail::isCommentOrBlank(line)) continue;
      const long lineNo = in_->lineNumber();
      const auto f = splitFields(line);
      const std::string_view name = f[0];
      DatasetRecord r;
      if (name == "FLASER") {
        parseFlaser(f, lineNo, r);
      } else if (name == "ROBOTLASER1") {
        parseRobotLaser(f, lineNo, r);
      } else if (name == "ODOM") {
        if (!options().odometry) continue;
        parseOdom(f, lineNo, r);
      } else if (name == "PARAM") {
        if (f.size() < 3) throwAt(path_, lineNo, "PARAM needs a name and a value");
        const std::string param(f[1]);
        if (isFrontOffsetParam(param)) frontOffset_ = parseNumber(f[2], path_, lineNo, param.c_str());
        continue;
      } else {
        continue;  // SYNC, RLASER, TRUEPOS, RAWLASER*, NMEA-*, ...
      }
      latestStamp_ = std::max(latestStamp_, r.stamp);
      heap_.push({std::move(r), seq_++});
      return true;
    }
    return false;
  }

  double stampAt(const std::vector<std::string_view>& f, size_t index, long lineNo) const {
    const double t = parseNumber(f[index], path_, lineNo, "ipc timestamp");
    if (t < 0.0) throwAt(path_, lineNo, "negative ipc timestamp");
    return t;
  }

  void parseFlaser(const std::vector<std::string_view>& f, long lineNo, DatasetRecord& r) {
    if (f.size() < 2) throwAt(path_, lineNo, "FLASER without its number of readings");
    const long long n = parseInteger(f[1], path_, lineNo, "FLASER number of readings");
    if (n <= 0 || n > 100000) throwAt(path_, lineNo, "FLASER number of readings out of range: " + std::to_string(n));
    const size_t need = static_cast<size_t>(n) + 10;  // name n [n] x y th ox oy oth ts host
    if (f.size() < need) {
      throwAt(path_, lineNo,
              "FLASER with " + std::to_string(n) + " readings needs at least " + std::to_string(need) +
                  " fields (readings, laser pose, odometry pose, ipc timestamp, host), got " +
                  std::to_string(f.size()));
    }
    if (f.size() > need + 1) {
      throwAt(path_, lineNo,
              "FLASER with " + std::to_string(n) + " readings has " + std::to_string(f.size()) +
                  " fields, expected " + std::to_string(need) + " or " + std::to_string(need + 1));
    }
    const size_t o = 2 + static_cast<size_t>(n);
    std::vector<float> ranges(static_cast<size_t>(n));
    for (size_t i = 0; i < ranges.size(); ++i) {
      const double v = parseNumber(f[2 + i], path_, lineNo, "FLASER range");
      ranges[i] = (v <= 0.0 || v >= rangeMax_) ? std::numeric_limits<float>::quiet_NaN()
                                               : static_cast<float>(v);
    }
    for (size_t i = 0; i < 3; ++i) parseNumber(f[o + i], path_, lineNo, "FLASER laser pose");
    const double ox = parseNumber(f[o + 3], path_, lineNo, "FLASER odom_x");
    const double oy = parseNumber(f[o + 4], path_, lineNo, "FLASER odom_y");
    const double oth = parseNumber(f[o + 5], path_, lineNo, "FLASER odom_theta");
    r.kind = DatasetRecord::Kind::kFrame;
    r.stamp = stampAt(f, o + 6, lineNo);
    if (options().scans) {
      double angleMin = 0.0, increment = 0.0;
      flaserAngles(ranges.size(), angleMin, increment);
      r.data.setLaserScan(LaserScan::fromRanges(ranges, angleMin, increment, 0.0, rangeMax_,
                                                Transform(frontOffset_, 0.0, 0.0)));
    }
    r.data.setStamp(r.stamp);
    r.data.setOdom(Transform(ox, oy, oth), Eigen::Matrix<double, 6, 6>::Identity());
  }

  void parseRobotLaser(const std::vector<std::string_view>& f, long lineNo, DatasetRecord& r) {
    if (f.size() < 10) throwAt(path_, lineNo, "ROBOTLASER1 too short");
    const double startAngle = parseNumber(f[2], path_, lineNo, "ROBOTLASER1 start_angle");
    parseNumber(f[3], path_, lineNo, "ROBOTLASER1 field_of_view");
    const double resolution = parseNumber(f[4], path_, lineNo, "ROBOTLASER1 angular_resolution");
    const double maxRange = parseNumber(f[5], path_, lineNo, "ROBOTLASER1 maximum_range");
    const long long n = parseInteger(f[8], path_, lineNo, "ROBOTLASER1 num_readings");
    if (n <= 0 || n > 100000 || f.size() < static_cast<size_t>(n) + 10) {
      throwAt(path_, lineNo, "ROBOTLASER1 num_readings " + std::to_string(n) + " does not fit the line");
    }
    const size_t mIndex = 9 + static_cast<size_t>(n);
    const long long m = parseInteger(f[mIndex], path_, lineNo, "ROBOTLASER1 num_remissions");
    if (m < 0 || m > 100000) throwAt(path_, lineNo, "ROBOTLASER1 num_remissions out of range");
    const size_t o = mIndex + 1 + static_cast<size_t>(m);  // laser pose
    const size_t need = o + 6 + 5 + 2;                       // poses, tv rv fsd ssd turn, ts host
    if (f.size() < need || f.size() > need + 1) {
      throwAt(path_, lineNo,
              "ROBOTLASER1 with " + std::to_string(n) + " readings and " + std::to_string(m) +
                  " remissions needs " + std::to_string(need) + " fields (+ logger timestamp), got " +
                  std::to_string(f.size()));
    }
    const double rangeMax = rangeMaxFixed_ ? rangeMax_ : maxRange;
    std::vector<float> ranges(static_cast<size_t>(n));
    for (size_t i = 0; i < ranges.size(); ++i) {
      const double v = parseNumber(f[9 + i], path_, lineNo, "ROBOTLASER1 range");
      ranges[i] = (v <= 0.0 || (rangeMax > 0.0 && v >= rangeMax))
                      ? std::numeric_limits<float>::quiet_NaN()
                      : static_cast<float>(v);
    }
    std::vector<float> intensities;
    if (m == n) {
      intensities.resize(static_cast<size_t>(m));
      for (size_t i = 0; i < intensities.size(); ++i) {
        intensities[i] = static_cast<float>(parseNumber(f[mIndex + 1 + i], path_, lineNo, "ROBOTLASER1 remission"));
      }
    }
    double v[6];
    for (int i = 0; i < 6; ++i) v[i] = parseNumber(f[o + i], path_, lineNo, "ROBOTLASER1 pose");
    const Transform laser(v[0], v[1], v[2]);
    const Transform robot(v[3], v[4], v[5]);
    r.kind = DatasetRecord::Kind::kFrame;
    r.stamp = stampAt(f, o + 11, lineNo);
    if (options().scans) {
      r.data.setLaserScan(LaserScan::fromRanges(ranges, startAngle, resolution, 0.0, rangeMax,
                                                (robot.inverse() * laser).to3DoF(), intensities));
    }
    r.data.setStamp(r.stamp);
    r.data.setOdom(robot, Eigen::Matrix<double, 6, 6>::Identity());
  }

  void parseOdom(const std::vector<std::string_view>& f, long lineNo, DatasetRecord& r) {
    // ODOM x y theta tv rv accel ipc_timestamp host [logger_timestamp]
    if (f.size() < 9 || f.size() > 10) {
      throwAt(path_, lineNo,
              "ODOM needs x y theta tv rv accel ipc_timestamp host [logger_timestamp], got " +
                  std::to_string(f.size() - 1) + " fields");
    }
    const double x = parseNumber(f[1], path_, lineNo, "ODOM x");
    const double y = parseNumber(f[2], path_, lineNo, "ODOM y");
    const double th = parseNumber(f[3], path_, lineNo, "ODOM theta");
    for (size_t i = 4; i < 7; ++i) parseNumber(f[i], path_, lineNo, "ODOM velocity");
    r.kind = DatasetRecord::Kind::kOdometry;
    r.stamp = stampAt(f, 7, lineNo);
    r.data.setStamp(r.stamp);
    r.data.setOdom(Transform(x, y, th), Eigen::Matrix<double, 6, 6>::Identity());
  }

  std::string path_;
  std::unique_ptr<TextLineReader> in_;
  double rangeMax_ = kDefaultRangeMax;
  bool rangeMaxFixed_ = false;
  double frontOffset_ = 0.0;
  int frames_ = -1;
  std::priority_queue<Buffered, std::vector<Buffered>, Later> heap_;
  long seq_ = 0;
  bool eof_ = false;
  double latestStamp_ = -std::numeric_limits<double>::infinity();
  double lastEmitted_ = -std::numeric_limits<double>::infinity();
  bool warnedDisorder_ = false;
  int frameId_ = 0;
};

[[maybe_unused]] const bool kRegistered = registerDatasetFormat(
    "carmen", [](const std::string& path, const DatasetReaderOptions& options) {
      return std::unique_ptr<DatasetReader>(new CarmenReader(path, options));
    });

}  // namespace
}  // namespace rtabmap

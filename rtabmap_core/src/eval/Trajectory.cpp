#include "rtabmap_core/eval/Trajectory.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "ReaderSupport.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap {

using eval_detail::parseInteger;
using eval_detail::parseNumber;
using eval_detail::splitFields;
using eval_detail::TextLineReader;
using eval_detail::throwAt;

// ---------------------------------------------------------------------------------------------
// Trajectory
// ---------------------------------------------------------------------------------------------

bool Trajectory::isSorted() const {
  for (size_t i = 1; i < poses.size(); ++i) {
    if (poses[i].stamp < poses[i - 1].stamp) return false;
  }
  return true;
}

void Trajectory::sortByStamp() {
  std::stable_sort(poses.begin(), poses.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.stamp < b.stamp; });
}

namespace {
size_t lowerBound(const std::vector<StampedPose>& poses, double stamp) {
  return static_cast<size_t>(
      std::lower_bound(poses.begin(), poses.end(), stamp,
                       [](const StampedPose& p, double s) { return p.stamp < s; }) -
      poses.begin());
}
}  // namespace

long Trajectory::nearest(double stamp, double maxDifference) const {
  if (!isSorted()) throw std::logic_error("Trajectory::nearest needs a trajectory sorted by stamp");
  const size_t i = lowerBound(poses, stamp);
  long best = -1;
  double bestDiff = std::numeric_limits<double>::infinity();
  if (i > 0) {  // the pose just before (the earlier one wins a tie)
    best = static_cast<long>(i - 1);
    bestDiff = stamp - poses[i - 1].stamp;
  }
  if (i < poses.size() && poses[i].stamp - stamp < bestDiff) {
    best = static_cast<long>(i);
    bestDiff = poses[i].stamp - stamp;
  }
  return (best >= 0 && bestDiff <= maxDifference) ? best : -1;
}

Transform Trajectory::interpolate(double stamp, double maxGap) const {
  if (!isSorted()) throw std::logic_error("Trajectory::interpolate needs a trajectory sorted by stamp");
  if (poses.empty()) return Transform();
  const size_t i = lowerBound(poses, stamp);
  constexpr double kExact = 1e-9;
  if (i < poses.size() && std::abs(poses[i].stamp - stamp) <= kExact) return poses[i].pose;
  if (i > 0 && std::abs(poses[i - 1].stamp - stamp) <= kExact) return poses[i - 1].pose;
  if (i == 0 || i >= poses.size()) return Transform();
  const StampedPose& a = poses[i - 1];
  const StampedPose& b = poses[i];
  // (A nanosecond of slack: samples 0.1 s apart have stamps 0.1 + 1 ulp apart.)
  if (a.pose.isNull() || b.pose.isNull() || b.stamp - a.stamp > maxGap + kExact) return Transform();
  const double t = (stamp - a.stamp) / (b.stamp - a.stamp);
  return a.pose.interpolate(t, b.pose);
}

double Trajectory::pathLength() const {
  double length = 0.0;
  const Transform* previous = nullptr;
  for (const auto& p : poses) {
    if (p.pose.isNull()) continue;
    if (previous) length += (p.pose.translation() - previous->translation()).norm();
    previous = &p.pose;
  }
  return length;
}

std::vector<Transform> Trajectory::transforms() const {
  std::vector<Transform> out;
  out.reserve(poses.size());
  for (const auto& p : poses) out.push_back(p.pose);
  return out;
}

std::vector<double> Trajectory::stamps() const {
  std::vector<double> out;
  out.reserve(poses.size());
  for (const auto& p : poses) out.push_back(p.stamp);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Formats
// ---------------------------------------------------------------------------------------------

TrajectoryFormat trajectoryFormatFromName(const std::string& name) {
  const std::string n = eval_detail::toLower(name);
  if (n == "auto") return TrajectoryFormat::kAuto;
  if (n == "tum") return TrajectoryFormat::kTum;
  if (n == "kitti") return TrajectoryFormat::kKitti;
  if (n == "g2o") return TrajectoryFormat::kG2o;
  if (n == "euroc") return TrajectoryFormat::kEuroc;
  throw FormatError("unknown trajectory format \"" + name + "\" (expected tum, kitti, g2o, euroc or auto)");
}

std::string trajectoryFormatName(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kAuto:
      return "auto";
    case TrajectoryFormat::kTum:
      return "tum";
    case TrajectoryFormat::kKitti:
      return "kitti";
    case TrajectoryFormat::kG2o:
      return "g2o";
    case TrajectoryFormat::kEuroc:
      return "euroc";
  }
  return "auto";
}

TrajectoryFormat detectTrajectoryFormat(const std::string& path) {
  TextLineReader in(path);
  std::string line;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    const auto blank = splitFields(line);
    const std::string first(blank.front());
    if (first.rfind("VERTEX_", 0) == 0 || first.rfind("EDGE_", 0) == 0 || first == "FIX" ||
        first.rfind("PARAMS_", 0) == 0) {
      return TrajectoryFormat::kG2o;
    }
    const auto fields = splitFields(line, true);
    long long ns = 0;
    if (line.find(',') != std::string::npos && fields.size() >= 8 &&
        eval_detail::tryParseInteger(fields[0], ns) && ns > 1000000000000LL) {
      return TrajectoryFormat::kEuroc;
    }
    for (auto f : fields) {
      double v = 0.0;
      if (!eval_detail::tryParseNumber(f, v)) {
        throwAt(path, in.lineNumber(), "not a trajectory file: '" + std::string(f) + "' is not a number");
      }
    }
    if (fields.size() == 12) return TrajectoryFormat::kKitti;
    if (fields.size() == 8) return TrajectoryFormat::kTum;
    throwAt(path, in.lineNumber(),
            "cannot tell the trajectory format from " + std::to_string(fields.size()) +
                " numbers per line (tum: 8 `t x y z qx qy qz qw`, kitti: 12, g2o: VERTEX_ lines)");
  }
  throw FormatError(path + ": empty trajectory file");
}

namespace {

Transform quaternionPose(double x, double y, double z, double qx, double qy, double qz, double qw,
                         const std::string& path, long line) {
  try {
    return Transform(x, y, z, qx, qy, qz, qw);
  } catch (const std::invalid_argument& e) {
    throwAt(path, line, std::string("invalid quaternion: ") + e.what());
  }
}

void readTum(TextLineReader& in, Trajectory& t) {
  std::string line;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    const long n = in.lineNumber();
    const auto f = splitFields(line, true);
    if (f.size() != 8) {
      throwAt(in.path(), n, "expected 8 values `timestamp tx ty tz qx qy qz qw`, got " + std::to_string(f.size()));
    }
    double v[8];
    for (int i = 0; i < 8; ++i) v[i] = parseNumber(f[i], in.path(), n, i == 0 ? "timestamp" : "pose value");
    t.add(v[0], quaternionPose(v[1], v[2], v[3], v[4], v[5], v[6], v[7], in.path(), n));
  }
}

void readKitti(TextLineReader& in, Trajectory& t) {
  std::string line;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    const long n = in.lineNumber();
    const auto f = splitFields(line, true);
    if (f.size() != 12) {
      throwAt(in.path(), n, "expected 12 values (3x4 pose, row-major), got " + std::to_string(f.size()));
    }
    double v[12];
    for (int i = 0; i < 12; ++i) v[i] = parseNumber(f[i], in.path(), n, "pose value");
    t.add(static_cast<double>(t.size()), Transform::fromArray12(v));
  }
}

void readG2o(TextLineReader& in, Trajectory& t) {
  std::string line;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    const long n = in.lineNumber();
    const auto f = splitFields(line);
    if (f[0] == "VERTEX_SE2") {
      if (f.size() != 5) throwAt(in.path(), n, "VERTEX_SE2 needs `id x y theta`");
      const long long id = parseInteger(f[1], in.path(), n, "vertex id");
      t.add(static_cast<double>(id), Transform(parseNumber(f[2], in.path(), n, "x"),
                                               parseNumber(f[3], in.path(), n, "y"),
                                               parseNumber(f[4], in.path(), n, "theta")));
    } else if (f[0] == "VERTEX_SE3:QUAT") {
      if (f.size() != 9) throwAt(in.path(), n, "VERTEX_SE3:QUAT needs `id x y z qx qy qz qw`");
      const long long id = parseInteger(f[1], in.path(), n, "vertex id");
      double v[7];
      for (int i = 0; i < 7; ++i) v[i] = parseNumber(f[2 + i], in.path(), n, "pose value");
      t.add(static_cast<double>(id), quaternionPose(v[0], v[1], v[2], v[3], v[4], v[5], v[6], in.path(), n));
    }
  }
  if (t.empty()) throw FormatError(in.path() + ": no VERTEX_SE2 or VERTEX_SE3:QUAT line (a graph of edges only has no poses)");
}

void readEuroc(TextLineReader& in, Trajectory& t) {
  std::string line;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    const long n = in.lineNumber();
    const auto f = splitFields(line, true);
    if (f.size() < 8) {
      throwAt(in.path(), n, "expected at least `timestamp_ns, px, py, pz, qw, qx, qy, qz`, got " +
                                std::to_string(f.size()) + " values");
    }
    const long long ns = parseInteger(f[0], in.path(), n, "timestamp [ns]");
    double v[7];
    for (int i = 0; i < 7; ++i) v[i] = parseNumber(f[1 + i], in.path(), n, "pose value");
    // p x y z, then q w x y z.
    t.add(static_cast<double>(ns) * 1e-9, quaternionPose(v[0], v[1], v[2], v[4], v[5], v[6], v[3], in.path(), n));
  }
}

void appendNumber(std::string& out, double v) {
  char buf[64];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  if (ec != std::errc()) throw std::logic_error("cannot format a number");
  out.append(buf, ptr);
}

}  // namespace

Trajectory readTrajectory(const std::string& path, TrajectoryFormat format) {
  if (format == TrajectoryFormat::kAuto) format = detectTrajectoryFormat(path);
  TextLineReader in(path);
  Trajectory t;
  switch (format) {
    case TrajectoryFormat::kTum:
      readTum(in, t);
      break;
    case TrajectoryFormat::kKitti:
      readKitti(in, t);
      break;
    case TrajectoryFormat::kG2o:
      readG2o(in, t);
      break;
    case TrajectoryFormat::kEuroc:
      readEuroc(in, t);
      break;
    case TrajectoryFormat::kAuto:
      break;
  }
  if (t.empty()) throw FormatError(path + ": no pose in the file");
  return t;
}

void writeTrajectory(const std::string& path, const Trajectory& trajectory, TrajectoryFormat format) {
  if (format == TrajectoryFormat::kAuto || format == TrajectoryFormat::kEuroc) {
    throw FormatError("writeTrajectory: format " + trajectoryFormatName(format) +
                      " cannot be written (use tum, kitti or g2o)");
  }
  // g2o ids: the stamps when they are distinct non-negative integers, else the row index.
  bool stampsAreIds = format == TrajectoryFormat::kG2o;
  if (stampsAreIds) {
    std::vector<double> ids;
    for (const auto& p : trajectory.poses) {
      if (p.pose.isNull()) continue;
      if (p.stamp < 0.0 || p.stamp != std::floor(p.stamp) || p.stamp > 2e9) stampsAreIds = false;
      ids.push_back(p.stamp);
    }
    std::sort(ids.begin(), ids.end());
    if (std::adjacent_find(ids.begin(), ids.end()) != ids.end()) stampsAreIds = false;
  }
  std::string out;
  if (format == TrajectoryFormat::kTum) out += "# timestamp tx ty tz qx qy qz qw\n";
  long index = 0;
  for (const auto& p : trajectory.poses) {
    if (p.pose.isNull()) continue;
    const Eigen::Vector3d t = p.pose.translation();
    if (format == TrajectoryFormat::kKitti) {
      double v[12];
      p.pose.toArray12(v);
      for (int i = 0; i < 12; ++i) {
        if (i) out += ' ';
        appendNumber(out, v[i]);
      }
    } else {
      Eigen::Quaterniond q = p.pose.quaternion();
      if (q.w() < 0.0) q.coeffs() = -q.coeffs();
      if (format == TrajectoryFormat::kTum) {
        appendNumber(out, p.stamp);
      } else {
        out += "VERTEX_SE3:QUAT ";
        out += std::to_string(stampsAreIds ? static_cast<long>(p.stamp) : index);
      }
      for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) {
        out += ' ';
        appendNumber(out, v);
      }
    }
    out += '\n';
    ++index;
  }
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) throw Error("cannot write the trajectory file " + path);
  file << out;
  file.close();
  if (!file) throw Error("error writing the trajectory file " + path);
}

}  // namespace rtabmap

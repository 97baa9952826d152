#include "rtabmap_core/geometry/LaserScan.h"

#include <opencv2/core.hpp>

#include <cmath>
#include <limits>
#include <cstring>
#include <stdexcept>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {

namespace {

// Offset of the first normal component (nx) in a point of each format, or -1.
int normalOffset(LaserScan::Format format) {
  switch (format) {
    case LaserScan::kXYNormal:
      return 2;  // x y nx ny nz
    case LaserScan::kXYINormal:
      return 3;  // x y i nx ny nz
    case LaserScan::kXYZNormal:
      return 3;  // x y z nx ny nz
    case LaserScan::kXYZINormal:
    case LaserScan::kXYZRGBNormal:
      return 4;  // x y z i|rgb nx ny nz
    default:
      return -1;
  }
}

}  // namespace

LaserScan::LaserScan()
    : format_(kUnknown), maxPoints_(0), rangeMin_(0.0), rangeMax_(0.0),
      localTransform_(Transform::Identity()) {}

LaserScan::LaserScan(const cv::Mat& data, int maxPoints, double rangeMin, double rangeMax,
                     Format format, const Transform& localTransform)
    : format_(format), maxPoints_(maxPoints), rangeMin_(rangeMin), rangeMax_(rangeMax),
      localTransform_(localTransform) {
  if (format < kUnknown || format > kXYZRGBNormal) {
    throw FormatError("LaserScan: unknown format " + std::to_string(static_cast<int>(format)));
  }
  if (data.empty()) return;
  if (format == kUnknown) {
    throw FormatError("LaserScan: a non-empty scan needs a format (got kUnknown)");
  }
  const int cn = channels(format);
  if (data.depth() != CV_32F || data.channels() != cn) {
    throw FormatError("LaserScan: format " + formatName(format) + " needs CV_32FC" +
                      std::to_string(cn) + " data, got depth " + std::to_string(data.depth()) +
                      " with " + std::to_string(data.channels()) + " channels");
  }
  if (data.rows == 1) {
    data_ = data;
  } else if (data.cols == 1) {
    // Nx1 (what a column of points gives): store as the documented 1xN.
    data_ = (data.isContinuous() ? data : data.clone()).reshape(cn, 1);
  } else {
    throw FormatError("LaserScan: data must be 1xN or Nx1 points, got " +
                      std::to_string(data.rows) + "x" + std::to_string(data.cols));
  }
}

LaserScan LaserScan::fromRanges(const std::vector<float>& ranges, double angleMin,
                                double angleIncrement, double rangeMin, double rangeMax,
                                const Transform& localTransform,
                                const std::vector<float>& intensities) {
  const bool withIntensity = !intensities.empty();
  if (withIntensity && intensities.size() != ranges.size()) {
    throw FormatError("LaserScan::fromRanges: " + std::to_string(intensities.size()) +
                      " intensities for " + std::to_string(ranges.size()) + " ranges");
  }
  const Format format = withIntensity ? kXYI : kXY;
  const int cn = channels(format);
  cv::Mat data(1, static_cast<int>(ranges.size()), CV_32FC(cn));
  int n = 0;
  for (size_t i = 0; i < ranges.size(); ++i) {
    const float r = ranges[i];
    // NaN/inf are "no return"; ranges outside the sensor limits are invalid by REP-117.
    if (!std::isfinite(r) || r < rangeMin || (rangeMax > 0.0 && r > rangeMax)) continue;
    const double a = angleMin + angleIncrement * static_cast<double>(i);
    float* p = data.ptr<float>(0) + n * cn;
    p[0] = static_cast<float>(r * std::cos(a));
    p[1] = static_cast<float>(r * std::sin(a));
    if (withIntensity) p[2] = intensities[i];
    ++n;
  }
  cv::Mat points = n > 0 ? cv::Mat(data.colRange(0, n)).clone() : cv::Mat();
  LaserScan scan(points, static_cast<int>(ranges.size()), rangeMin, rangeMax, format, localTransform);
  if (!ranges.empty() && angleIncrement != 0.0) {
    scan.setBeamGeometry(angleMin, angleMin + angleIncrement * static_cast<double>(ranges.size() - 1),
                         angleIncrement);
  }
  return scan;
}

void LaserScan::setBeamGeometry(double angleMin, double angleMax, double angleIncrement) {
  // A planar scan spans at most a turn: angles beyond +-4 pi are corrupt data, not a sensor.
  constexpr double kMaxAngle = 4.0 * M_PI;
  if (!std::isfinite(angleMin) || !std::isfinite(angleMax) || !std::isfinite(angleIncrement) ||
      std::abs(angleMin) > kMaxAngle || std::abs(angleMax) > kMaxAngle ||
      (angleIncrement != 0.0 && (angleMax - angleMin) / angleIncrement < 0.0)) {
    throw FormatError("LaserScan: invalid beam geometry (angle_min " + std::to_string(angleMin) +
                      ", angle_max " + std::to_string(angleMax) + ", increment " +
                      std::to_string(angleIncrement) + ")");
  }
  angleMin_ = angleMin;
  angleMax_ = angleMax;
  angleIncrement_ = angleIncrement;
}

std::vector<float> LaserScan::toRanges() const {
  if (!hasBeamGeometry() || !is2d()) return {};
  const int beams = static_cast<int>(std::lround((angleMax_ - angleMin_) / angleIncrement_)) + 1;
  std::vector<float> ranges(static_cast<size_t>(std::max(beams, 0)),
                            std::numeric_limits<float>::infinity());
  for (int i = 0; i < size(); ++i) {
    const float* p = data_.ptr<float>(0) + static_cast<size_t>(i) * data_.channels();
    const double a = std::atan2(p[1], p[0]);
    // Beam index of this point's bearing, unwrapping so a scan crossing +-pi maps correctly.
    double k = (a - angleMin_) / angleIncrement_;
    // In closed form (whole turns), not by stepping: a corrupt geometry with huge angles would
    // step for ever (found by fuzzing the ROS conversion).
    const double turn = 2.0 * M_PI / std::abs(angleIncrement_);
    if (k < -0.5) k += std::ceil((-0.5 - k) / turn) * turn;
    if (k > beams - 0.5 + 1e-9) {
      const double wanted = std::ceil((k - (beams - 0.5 + 1e-9)) / turn);
      const double allowed = std::floor((k + 0.5) / turn);  // keeps k >= -0.5
      k -= std::min(wanted, allowed) * turn;
    }
    const long idx = std::lround(k);
    if (idx < 0 || idx >= beams) continue;
    ranges[static_cast<size_t>(idx)] = std::hypot(p[0], p[1]);
  }
  return ranges;
}

int LaserScan::channels(Format format) {
  switch (format) {
    case kXY:
      return 2;
    case kXYI:
      return 3;
    case kXYNormal:
      return 5;
    case kXYINormal:
      return 6;
    case kXYZ:
      return 3;
    case kXYZI:
    case kXYZRGB:
      return 4;
    case kXYZNormal:
      return 6;
    case kXYZINormal:
    case kXYZRGBNormal:
      return 7;
    case kUnknown:
    default:
      return 0;
  }
}

bool LaserScan::is2d(Format format) {
  return format == kXY || format == kXYI || format == kXYNormal || format == kXYINormal;
}

bool LaserScan::hasNormals(Format format) { return normalOffset(format) >= 0; }

bool LaserScan::hasIntensity(Format format) {
  return format == kXYI || format == kXYINormal || format == kXYZI || format == kXYZINormal;
}

bool LaserScan::hasRGB(Format format) { return format == kXYZRGB || format == kXYZRGBNormal; }

std::string LaserScan::formatName(Format format) {
  switch (format) {
    case kXY:
      return "XY";
    case kXYI:
      return "XYI";
    case kXYNormal:
      return "XYNormal";
    case kXYINormal:
      return "XYINormal";
    case kXYZ:
      return "XYZ";
    case kXYZI:
      return "XYZI";
    case kXYZRGB:
      return "XYZRGB";
    case kXYZNormal:
      return "XYZNormal";
    case kXYZINormal:
      return "XYZINormal";
    case kXYZRGBNormal:
      return "XYZRGBNormal";
    case kUnknown:
    default:
      return "Unknown";
  }
}

Eigen::Vector3f LaserScan::point(int i) const {
  if (i < 0 || i >= size()) {
    throw std::out_of_range("LaserScan::point: index " + std::to_string(i) + " of " +
                            std::to_string(size()));
  }
  const float* p = data_.ptr<float>(0) + static_cast<size_t>(i) * data_.channels();
  return Eigen::Vector3f(p[0], p[1], is2d() ? 0.0f : p[2]);
}

LaserScan LaserScan::transformedToBase() const {
  LaserScan out = *this;
  out.localTransform_ = Transform::Identity();
  out.angleMin_ = out.angleMax_ = out.angleIncrement_ = 0.0;
  if (data_.empty() || localTransform_.isNull() || localTransform_.isIdentity(0.0)) {
    out.data_ = data_.clone();
    return out;
  }
  const Eigen::Matrix3f R = localTransform_.rotationMatrix().cast<float>();
  const Eigen::Vector3f t = localTransform_.translation().cast<float>();
  const bool planar = is2d();
  const int cn = data_.channels();
  const int nOff = normalOffset(format_);
  cv::Mat dst = data_.clone();
  for (int i = 0; i < dst.cols; ++i) {
    float* p = dst.ptr<float>(0) + static_cast<size_t>(i) * cn;
    const Eigen::Vector3f q = R * Eigen::Vector3f(p[0], p[1], planar ? 0.0f : p[2]) + t;
    // A 2D format has no z: the scan stays in the base's horizontal plane (the sensor's
    // height is dropped, as a planar lidar is meant to be mounted level).
    p[0] = q.x();
    p[1] = q.y();
    if (!planar) p[2] = q.z();
    if (nOff >= 0) {
      const Eigen::Vector3f n = R * Eigen::Vector3f(p[nOff], p[nOff + 1], p[nOff + 2]);
      p[nOff] = n.x();
      p[nOff + 1] = n.y();
      p[nOff + 2] = n.z();
    }
  }
  out.data_ = dst;
  return out;
}

LaserScan LaserScan::filtered(double rangeMin, double rangeMax, int maxPoints) const {
  LaserScan out = *this;
  if (data_.empty()) return out;
  const int cn = data_.channels();
  const bool planar = is2d();
  const double min2 = rangeMin > 0.0 ? rangeMin * rangeMin : 0.0;
  const double max2 = rangeMax > 0.0 ? rangeMax * rangeMax : 0.0;
  std::vector<int> kept;
  kept.reserve(data_.cols);
  for (int i = 0; i < data_.cols; ++i) {
    const float* p = data_.ptr<float>(0) + static_cast<size_t>(i) * cn;
    const double d2 = double(p[0]) * p[0] + double(p[1]) * p[1] + (planar ? 0.0 : double(p[2]) * p[2]);
    if (!std::isfinite(d2)) continue;
    if (min2 > 0.0 && d2 < min2) continue;
    if (max2 > 0.0 && d2 > max2) continue;
    kept.push_back(i);
  }
  const int candidates = static_cast<int>(kept.size());
  int outCount = candidates;
  if (maxPoints > 0 && candidates > maxPoints) outCount = maxPoints;
  cv::Mat dst(1, outCount, data_.type());
  for (int j = 0; j < outCount; ++j) {
    // Uniform downsampling: evenly spaced indices over the kept points.
    const int src = outCount == candidates
                        ? kept[j]
                        : kept[static_cast<size_t>(static_cast<int64_t>(j) * candidates / outCount)];
    std::memcpy(dst.ptr<float>(0) + static_cast<size_t>(j) * cn,
                data_.ptr<float>(0) + static_cast<size_t>(src) * cn, sizeof(float) * cn);
  }
  out.data_ = outCount > 0 ? dst : cv::Mat();
  if (rangeMin > 0.0 && rangeMin > out.rangeMin_) out.rangeMin_ = rangeMin;
  if (rangeMax > 0.0 && (out.rangeMax_ <= 0.0 || rangeMax < out.rangeMax_)) out.rangeMax_ = rangeMax;
  if (outCount < candidates && candidates > 0 && out.maxPoints_ > 0) {
    // A downsampled scan can only match a fraction of the beams of a full one: scale maxPoints
    // so the ICP correspondence ratio stays comparable.
    out.maxPoints_ = static_cast<int>(
        std::ceil(static_cast<double>(out.maxPoints_) * outCount / candidates));
  }
  return out;
}

}  // namespace rtabmap

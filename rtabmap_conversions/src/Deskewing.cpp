#include "rtabmap_conversions/Deskewing.h"

#include <laser_geometry/laser_geometry.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "Support.h"
#include "rtabmap_conversions/TfLookup.h"

namespace rtabmap_conversions {

namespace {

// Times above this are absolute (seconds since the epoch), not offsets within a sweep.
constexpr double kAbsoluteTime = 1e6;

const sensor_msgs::PointField* findField(const sensor_msgs::PointCloud2& cloud, const std::string& name) {
  for (const sensor_msgs::PointField& f : cloud.fields) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

size_t fieldSize(uint8_t datatype) {
  using F = sensor_msgs::PointField;
  switch (datatype) {
    case F::INT8: case F::UINT8: return 1;
    case F::INT16: case F::UINT16: return 2;
    case F::INT32: case F::UINT32: case F::FLOAT32: return 4;
    case F::FLOAT64: return 8;
    default: return 0;
  }
}

double readValue(const uint8_t* p, uint8_t datatype) {
  using F = sensor_msgs::PointField;
  auto as = [p](auto v) {
    std::memcpy(&v, p, sizeof(v));
    return static_cast<double>(v);
  };
  switch (datatype) {
    case F::INT8: return as(int8_t());
    case F::UINT8: return as(uint8_t());
    case F::INT16: return as(int16_t());
    case F::UINT16: return as(uint16_t());
    case F::INT32: return as(int32_t());
    case F::UINT32: return as(uint32_t());
    case F::FLOAT32: return as(float());
    default: return as(double());
  }
}

// The time field and the scale that turns its values into seconds.
const sensor_msgs::PointField* timeField(const sensor_msgs::PointCloud2& cloud, double* scale) {
  *scale = 1.0;
  if (const sensor_msgs::PointField* t = findField(cloud, "t")) {
    // Ouster writes nanoseconds as uint32; a float "t" is already seconds.
    if (t->datatype != sensor_msgs::PointField::FLOAT32 && t->datatype != sensor_msgs::PointField::FLOAT64) {
      *scale = 1e-9;
    }
    return t;
  }
  for (const char* name : {"time", "stamps", "timestamp"}) {
    if (const sensor_msgs::PointField* f = findField(cloud, name)) return f;
  }
  return nullptr;
}

// Field `name` is float32 and lies within each point.
bool floatField(const sensor_msgs::PointCloud2& cloud, const std::string& name, uint32_t* offset) {
  const sensor_msgs::PointField* f = findField(cloud, name);
  if (!f || f->datatype != sensor_msgs::PointField::FLOAT32 || f->offset + 4 > cloud.point_step) return false;
  *offset = f->offset;
  return true;
}

size_t pointCount(const sensor_msgs::PointCloud2& cloud) {
  return static_cast<size_t>(cloud.width) * static_cast<size_t>(cloud.height);
}

bool dataHoldsPoints(const sensor_msgs::PointCloud2& cloud) {
  if (cloud.point_step == 0 || cloud.row_step < static_cast<uint64_t>(cloud.width) * cloud.point_step) return false;
  return cloud.data.size() >= static_cast<size_t>(cloud.row_step) * cloud.height;
}

const uint8_t* pointBytes(const sensor_msgs::PointCloud2& cloud, size_t i) {
  const size_t row = i / cloud.width, col = i % cloud.width;
  return cloud.data.data() + row * cloud.row_step + col * cloud.point_step;
}

}  // namespace

SweepMotion::SweepMotion(const rtabmap::Transform& first, double firstDt, const rtabmap::Transform& last,
                         double lastDt)
    : first_(first), last_(last), firstDt_(firstDt), lastDt_(lastDt) {}

std::optional<SweepMotion> SweepMotion::fromTf(const tf2::BufferCore& buffer, const std::string& fixedFrame,
                                               const std::string& sensorFrame, const ros::Time& stamp,
                                               double firstDt, double lastDt, double waitSeconds,
                                               std::string* error) {
  const auto motionTo = [&](double dt) {
    return lookupMotion(buffer, fixedFrame, sensorFrame, stamp, stamp + ros::Duration(dt), waitSeconds, error);
  };
  const rtabmap::Transform first = motionTo(firstDt);
  if (first.isNull()) return std::nullopt;
  const rtabmap::Transform last = lastDt == firstDt ? first : motionTo(lastDt);
  if (last.isNull()) return std::nullopt;
  return SweepMotion(first, firstDt, last, lastDt);
}

SweepMotion SweepMotion::fromVelocity(const rtabmap::Transform& motion, double interval) {
  // Identity at 0 and `motion` at `interval`: at(dt) extrapolates the same line for any dt.
  return SweepMotion(rtabmap::Transform::Identity(), 0.0, motion, interval);
}

SweepMotion SweepMotion::fromEnds(const rtabmap::Transform& atFirst, double firstDt, const rtabmap::Transform& atLast,
                                  double lastDt) {
  return SweepMotion(atFirst, firstDt, atLast, lastDt);
}

rtabmap::Transform SweepMotion::at(double dt) const {
  if (lastDt_ == firstDt_) return first_;
  return first_.interpolate((dt - firstDt_) / (lastDt_ - firstDt_), last_);
}

sensor_msgs::PointCloud2 timedCloudFromScan(const sensor_msgs::LaserScan& scan) {
  // One projector for the process: it caches the beams' unit vectors per geometry, under its
  // own mutex.
  static laser_geometry::LaserProjection projector;
  int channels = laser_geometry::channel_option::Timestamp;
  if (!scan.intensities.empty()) channels |= laser_geometry::channel_option::Intensity;
  sensor_msgs::PointCloud2 cloud;
  projector.projectLaser(scan, cloud, -1.0, channels);
  return cloud;
}

std::optional<std::vector<double>> pointTimes(const sensor_msgs::PointCloud2& cloud, std::string* error) {
  if (cloud.is_bigendian) return detail::fail(error, "big-endian clouds are not supported");
  double scale = 1.0;
  const sensor_msgs::PointField* f = timeField(cloud, &scale);
  if (!f) {
    return detail::fail(error, "the cloud has no per-point time field (t, time, stamps or timestamp), so it "
                               "cannot be deskewed");
  }
  const size_t size = fieldSize(f->datatype);
  if (size == 0 || f->offset + size > cloud.point_step || !dataHoldsPoints(cloud)) {
    return detail::fail(error, "time field '" + f->name + "' lies outside the cloud's points");
  }
  const size_t n = pointCount(cloud);
  std::vector<double> times(n);
  const double stamp = cloud.header.stamp.toSec();
  for (size_t i = 0; i < n; ++i) {
    const double t = readValue(pointBytes(cloud, i) + f->offset, f->datatype) * scale;
    times[i] = t > kAbsoluteTime ? t - stamp : t;
  }
  return times;
}

bool deskewCloud(sensor_msgs::PointCloud2& cloud, const std::vector<double>& times, const SweepMotion& motion,
                 std::string* error) {
  uint32_t ox = 0, oy = 0, oz = 0;
  if (!floatField(cloud, "x", &ox) || !floatField(cloud, "y", &oy) || !floatField(cloud, "z", &oz)) {
    if (error) *error = "deskewing needs float32 x, y, z fields within each point";
    return false;
  }
  if (!dataHoldsPoints(cloud) || times.size() != pointCount(cloud)) {
    if (error) *error = "deskewing: " + std::to_string(times.size()) + " times for " +
                        std::to_string(pointCount(cloud)) + " points";
    return false;
  }
  for (size_t i = 0; i < times.size(); ++i) {
    uint8_t* p = &cloud.data[(i / cloud.width) * cloud.row_step + (i % cloud.width) * cloud.point_step];
    float xyz[3];
    std::memcpy(&xyz[0], p + ox, 4);
    std::memcpy(&xyz[1], p + oy, 4);
    std::memcpy(&xyz[2], p + oz, 4);
    if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2])) continue;
    const Eigen::Vector3d q = motion.at(times[i]).toEigen() * Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
    const float out[3] = {float(q.x()), float(q.y()), float(q.z())};
    std::memcpy(p + ox, &out[0], 4);
    std::memcpy(p + oy, &out[1], 4);
    std::memcpy(p + oz, &out[2], 4);
  }
  return true;
}

rtabmap::LaserScan planarScan(const rtabmap::LaserScan& cloud) {
  if (cloud.is2d() || cloud.empty()) return cloud;
  const bool intensity = cloud.hasIntensity();
  const int inChannels = cloud.data().channels();
  cv::Mat data(1, cloud.size(), CV_32FC(intensity ? 3 : 2));
  for (int i = 0; i < cloud.size(); ++i) {
    const float* in = cloud.data().ptr<float>(0) + static_cast<size_t>(i) * inChannels;
    float* out = data.ptr<float>(0) + static_cast<size_t>(i) * data.channels();
    out[0] = in[0];
    out[1] = in[1];
    if (intensity) out[2] = in[3];  // XYZI...: intensity follows z
  }
  return rtabmap::LaserScan(data, cloud.maxPoints(), cloud.rangeMin(), cloud.rangeMax(),
                            intensity ? rtabmap::LaserScan::kXYI : rtabmap::LaserScan::kXY,
                            cloud.localTransform());
}

}  // namespace rtabmap_conversions

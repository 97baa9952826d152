#include "rtabmap_conversions/PointCloudConversions.h"

#include <sensor_msgs/PointField.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "Support.h"

namespace rtabmap_conversions {

namespace {

using sensor_msgs::PointField;

int fieldSize(uint8_t datatype) {
  switch (datatype) {
    case PointField::INT8:
    case PointField::UINT8:
      return 1;
    case PointField::INT16:
    case PointField::UINT16:
      return 2;
    case PointField::INT32:
    case PointField::UINT32:
    case PointField::FLOAT32:
      return 4;
    case PointField::FLOAT64:
      return 8;
    default:
      return 0;
  }
}

// One field value as float, whatever its stored type (lidars store intensity as uint8/16,
// some drivers x/y/z as float64).
float readValue(const uint8_t* p, uint8_t datatype) {
  switch (datatype) {
    case PointField::INT8: return static_cast<float>(*reinterpret_cast<const int8_t*>(p));
    case PointField::UINT8: return static_cast<float>(*p);
    case PointField::INT16: { int16_t v; std::memcpy(&v, p, 2); return v; }
    case PointField::UINT16: { uint16_t v; std::memcpy(&v, p, 2); return v; }
    case PointField::INT32: { int32_t v; std::memcpy(&v, p, 4); return static_cast<float>(v); }
    case PointField::UINT32: { uint32_t v; std::memcpy(&v, p, 4); return static_cast<float>(v); }
    case PointField::FLOAT32: { float v; std::memcpy(&v, p, 4); return v; }
    case PointField::FLOAT64: { double v; std::memcpy(&v, p, 8); return static_cast<float>(v); }
    default: return 0.0f;
  }
}

struct Field {
  const PointField* field = nullptr;
  explicit operator bool() const { return field != nullptr; }
};

Field findField(const sensor_msgs::PointCloud2& msg, std::initializer_list<const char*> names) {
  for (const char* name : names) {
    for (const PointField& f : msg.fields) {
      if (f.name == name) return Field{&f};
    }
  }
  return Field{};
}

rtabmap::LaserScan::Format formatOf(bool intensity, bool rgb, bool normals) {
  using S = rtabmap::LaserScan;
  if (intensity) return normals ? S::kXYZINormal : S::kXYZI;
  if (rgb) return normals ? S::kXYZRGBNormal : S::kXYZRGB;
  return normals ? S::kXYZNormal : S::kXYZ;
}

}  // namespace

std::optional<rtabmap::LaserScan> laserScanFromCloudMsg(const sensor_msgs::PointCloud2& msg,
                                                        const rtabmap::Transform& localTransform, std::string* error,
                                                        double rangeMin, double rangeMax) {
  const std::string what = "PointCloud2 of frame '" + msg.header.frame_id + "'";
  const Field x = findField(msg, {"x"}), y = findField(msg, {"y"}), z = findField(msg, {"z"});
  if (!x || !y || !z) {
    std::vector<std::string> names;
    for (const PointField& f : msg.fields) names.push_back(f.name);
    return detail::fail(error, what + " has no x, y and z fields (fields: " + detail::listString(names) + ")");
  }
  if (msg.is_bigendian) return detail::fail(error, what + " is big-endian, which is not supported");
  const Field intensity = findField(msg, {"intensity", "i"});
  const Field rgb = intensity ? Field{} : findField(msg, {"rgb", "rgba"});
  const Field nx = findField(msg, {"normal_x"}), ny = findField(msg, {"normal_y"}), nz = findField(msg, {"normal_z"});
  const bool normals = nx && ny && nz;

  std::vector<Field> used = {x, y, z};
  if (intensity) used.push_back(intensity);
  if (rgb) used.push_back(rgb);
  if (normals) used.insert(used.end(), {nx, ny, nz});
  for (const Field& f : used) {
    const int size = fieldSize(f.field->datatype);
    if (size == 0 || uint64_t(f.field->offset) + size > msg.point_step) {
      return detail::fail(error, what + ": field '" + f.field->name + "' (datatype " +
                                     std::to_string(f.field->datatype) + ", offset " + std::to_string(f.field->offset) +
                                     ") does not fit in a point of " + std::to_string(msg.point_step) + " bytes");
    }
  }
  if (rgb && fieldSize(rgb.field->datatype) != 4) {
    return detail::fail(error, what + ": field '" + rgb.field->name + "' must be 4 bytes (packed colour)");
  }
  const uint64_t points = uint64_t(msg.width) * msg.height;
  if (points > 0 && (msg.row_step < uint64_t(msg.point_step) * msg.width ||
                     uint64_t(msg.row_step) * msg.height > msg.data.size())) {
    return detail::fail(error, what + ": " + std::to_string(msg.width) + "x" + std::to_string(msg.height) +
                                   " points of " + std::to_string(msg.point_step) + " bytes with row_step " +
                                   std::to_string(msg.row_step) + " do not fit in " +
                                   std::to_string(msg.data.size()) + " data bytes");
  }

  const rtabmap::LaserScan::Format format = formatOf(bool(intensity), bool(rgb), normals);
  const int cn = rtabmap::LaserScan::channels(format);
  cv::Mat data(1, static_cast<int>(points), CV_32FC(cn));
  int kept = 0;
  // Fuzzing fix (fuzz/regressions/ros_point_cloud2): a cloud of width 0 and a huge height
  // passes the size checks (0 bytes per row) and looped over 4e9 empty rows: no row then.
  const uint32_t rows = msg.width == 0 ? 0 : msg.height;
  for (uint32_t row = 0; row < rows; ++row) {
    const uint8_t* rowPtr = msg.data.data() + size_t(row) * msg.row_step;
    for (uint32_t col = 0; col < msg.width; ++col) {
      const uint8_t* p = rowPtr + size_t(col) * msg.point_step;
      const float px = readValue(p + x.field->offset, x.field->datatype);
      const float py = readValue(p + y.field->offset, y.field->datatype);
      const float pz = readValue(p + z.field->offset, z.field->datatype);
      if (!std::isfinite(px) || !std::isfinite(py) || !std::isfinite(pz)) continue;
      float* out = data.ptr<float>(0) + size_t(kept) * cn;
      int c = 0;
      out[c++] = px;
      out[c++] = py;
      out[c++] = pz;
      if (intensity) out[c++] = readValue(p + intensity.field->offset, intensity.field->datatype);
      // Packed colour: the 4 bytes are copied as they are (PCL's float-punned 0x00RRGGBB).
      if (rgb) std::memcpy(&out[c++], p + rgb.field->offset, 4);
      if (normals) {
        out[c++] = readValue(p + nx.field->offset, nx.field->datatype);
        out[c++] = readValue(p + ny.field->offset, ny.field->datatype);
        out[c++] = readValue(p + nz.field->offset, nz.field->datatype);
      }
      ++kept;
    }
  }
  const cv::Mat keptPoints = kept > 0 ? cv::Mat(data.colRange(0, kept)).clone() : cv::Mat();
  try {
    return rtabmap::LaserScan(keptPoints, static_cast<int>(points), rangeMin, rangeMax, format, localTransform);
  } catch (const std::exception& e) {
    return detail::fail(error, what + ": " + e.what());
  }
}

sensor_msgs::PointCloud2 laserScanToCloudMsg(const rtabmap::LaserScan& scan, const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 msg;
  msg.header = header;
  msg.height = 1;
  msg.is_bigendian = false;
  msg.is_dense = true;  // non-finite points never enter a LaserScan
  const bool planar = scan.is2d();
  std::vector<std::string> names = {"x", "y", "z"};
  if (scan.hasIntensity()) names.push_back("intensity");
  if (scan.hasRGB()) names.push_back("rgb");
  if (scan.hasNormals()) names.insert(names.end(), {"normal_x", "normal_y", "normal_z"});
  for (size_t i = 0; i < names.size(); ++i) {
    PointField f;
    f.name = names[i];
    f.offset = static_cast<uint32_t>(4 * i);
    f.datatype = PointField::FLOAT32;
    f.count = 1;
    msg.fields.push_back(f);
  }
  const int outChannels = static_cast<int>(names.size());
  msg.point_step = static_cast<uint32_t>(4 * outChannels);
  msg.width = static_cast<uint32_t>(scan.size());
  msg.row_step = msg.point_step * msg.width;
  msg.data.resize(msg.row_step);
  if (scan.empty()) return msg;
  const int cn = scan.data().channels();
  const float* in = scan.data().ptr<float>(0);
  std::vector<float> point(static_cast<size_t>(outChannels), 0.0f);
  for (int i = 0; i < scan.size(); ++i, in += cn) {
    if (planar) {
      // x y, then z = 0, then the remaining channels in order (intensity, normals).
      point[0] = in[0];
      point[1] = in[1];
      point[2] = 0.0f;
      std::copy(in + 2, in + cn, point.begin() + 3);
    } else {
      std::copy(in, in + cn, point.begin());
    }
    std::memcpy(msg.data.data() + size_t(i) * msg.point_step, point.data(), msg.point_step);
  }
  return msg;
}

}  // namespace rtabmap_conversions

// Point clouds as PLY and PCD files, binary little endian (see MapIO.h). Both formats are an
// ASCII header followed by fixed-size records; writing them here spares a dependency on pcl_io.
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/MapIO.h"

namespace rtabmap {

namespace {

// Every platform we build for is little endian; say so loudly if that ever changes.
static_assert(sizeof(float) == 4, "float must be 32 bits");
inline bool littleEndian() {
  const uint16_t one = 1;
  unsigned char b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

std::ofstream openForWriting(const Cloud& cloud, const std::string& path) {
  if (cloud.empty()) throw FormatError("cannot write " + path + ": the cloud has no point");
  if (!littleEndian()) throw FormatError("writing " + path + ": only little-endian hosts are supported");
  std::ofstream f(path, std::ios::binary);
  if (!f) throw FormatError("cannot write " + path);
  return f;
}

std::string readHeaderLine(std::istream& in, const std::string& path) {
  std::string line;
  if (!std::getline(in, line)) throw FormatError(path + ": truncated header");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

}  // namespace

void writePly(const Cloud& cloud, const std::string& path) {
  std::ofstream f = openForWriting(cloud, path);
  const bool rgb = cloud.hasColors();
  f << "ply\nformat binary_little_endian 1.0\ncomment written by rtabmap_ros\n"
    << "element vertex " << cloud.size() << "\n"
    << "property float x\nproperty float y\nproperty float z\n";
  if (rgb) f << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  f << "end_header\n";
  std::vector<char> record(12 + (rgb ? 3 : 0));
  for (size_t i = 0; i < cloud.size(); ++i) {
    std::memcpy(record.data(), &cloud.points[i], 12);
    if (rgb) std::memcpy(record.data() + 12, &cloud.colors[i], 3);
    f.write(record.data(), static_cast<std::streamsize>(record.size()));
  }
  if (!f) throw FormatError("cannot write " + path);
}

void writePcd(const Cloud& cloud, const std::string& path) {
  std::ofstream f = openForWriting(cloud, path);
  const bool rgb = cloud.hasColors();
  f << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
    << "FIELDS x y z" << (rgb ? " rgb" : "") << "\n"
    << "SIZE 4 4 4" << (rgb ? " 4" : "") << "\n"
    << "TYPE F F F" << (rgb ? " U" : "") << "\n"
    << "COUNT 1 1 1" << (rgb ? " 1" : "") << "\n"
    << "WIDTH " << cloud.size() << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
    << "POINTS " << cloud.size() << "\nDATA binary\n";
  std::vector<char> record(12 + (rgb ? 4 : 0));
  for (size_t i = 0; i < cloud.size(); ++i) {
    std::memcpy(record.data(), &cloud.points[i], 12);
    if (rgb) {
      const cv::Vec3b& c = cloud.colors[i];
      const uint32_t packed = (uint32_t(c[0]) << 16) | (uint32_t(c[1]) << 8) | uint32_t(c[2]);
      std::memcpy(record.data() + 12, &packed, 4);
    }
    f.write(record.data(), static_cast<std::streamsize>(record.size()));
  }
  if (!f) throw FormatError("cannot write " + path);
}

Cloud readPly(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw FormatError("cannot read " + path);
  if (readHeaderLine(f, path) != "ply") throw FormatError(path + ": not a PLY file");
  size_t count = 0;
  std::vector<std::string> properties;
  bool binaryLE = false;
  for (std::string line = readHeaderLine(f, path); line != "end_header"; line = readHeaderLine(f, path)) {
    std::istringstream s(line);
    std::string word;
    s >> word;
    if (word == "format") {
      std::string format;
      s >> format;
      binaryLE = format == "binary_little_endian";
    } else if (word == "element") {
      std::string name;
      s >> name >> count;
      if (name != "vertex") throw FormatError(path + ": only vertex elements are supported");
    } else if (word == "property") {
      std::string type, name;
      s >> type >> name;
      properties.push_back(type + " " + name);
    }
  }
  const bool xyz = properties.size() >= 3 && properties[0] == "float x" && properties[1] == "float y" &&
                   properties[2] == "float z";
  const bool rgb = properties.size() == 6 && properties[3] == "uchar red" &&
                   properties[4] == "uchar green" && properties[5] == "uchar blue";
  if (!binaryLE || !xyz || !(properties.size() == 3 || rgb)) {
    throw FormatError(path + ": expected a binary little-endian PLY of float x y z [uchar red green blue]");
  }
  Cloud cloud;
  cloud.points.resize(count);
  if (rgb) cloud.colors.resize(count);
  for (size_t i = 0; i < count; ++i) {
    f.read(reinterpret_cast<char*>(&cloud.points[i]), 12);
    if (rgb) f.read(reinterpret_cast<char*>(&cloud.colors[i]), 3);
  }
  if (!f) throw FormatError(path + ": truncated (expected " + std::to_string(count) + " vertices)");
  return cloud;
}

Cloud readPcd(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw FormatError("cannot read " + path);
  std::string fields;
  size_t count = 0;
  for (;;) {
    const std::string line = readHeaderLine(f, path);
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (key == "FIELDS") {
      std::getline(s, fields);
    } else if (key == "POINTS") {
      s >> count;
    } else if (key == "DATA") {
      std::string kind;
      s >> kind;
      if (kind != "binary") throw FormatError(path + ": only binary PCD data is supported (got " + kind + ")");
      break;
    }
  }
  const bool rgb = fields == " x y z rgb";
  if (fields != " x y z" && !rgb) throw FormatError(path + ": expected fields x y z [rgb] (got" + fields + ")");
  Cloud cloud;
  cloud.points.resize(count);
  if (rgb) cloud.colors.resize(count);
  for (size_t i = 0; i < count; ++i) {
    f.read(reinterpret_cast<char*>(&cloud.points[i]), 12);
    if (rgb) {
      uint32_t packed = 0;
      f.read(reinterpret_cast<char*>(&packed), 4);
      cloud.colors[i] = cv::Vec3b((packed >> 16) & 0xff, (packed >> 8) & 0xff, packed & 0xff);
    }
  }
  if (!f) throw FormatError(path + ": truncated (expected " + std::to_string(count) + " points)");
  return cloud;
}

}  // namespace rtabmap

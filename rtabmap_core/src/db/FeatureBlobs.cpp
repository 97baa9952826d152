// Node-word features and statistics blobs (declared in Blobs.h).
#include <cstdint>
#include <cstdio>
#include <sstream>

#include "Blobs.h"
#include "ByteIO.h"

namespace rtabmap::db::blob {

Bytes encodeWordIds(const std::vector<int>& ids) {
  std::vector<int32_t> values(ids.begin(), ids.end());
  return encodeArray(values);
}

std::vector<int> decodeWordIds(const unsigned char* data, size_t size) {
  const std::vector<int32_t> values = decodeArray<int32_t>(data, size, "word ids");
  return std::vector<int>(values.begin(), values.end());
}

namespace {
constexpr size_t kKeypointBytes = 5 * sizeof(float) + 2 * sizeof(int32_t);
}

Bytes encodeKeypoints(const std::vector<cv::KeyPoint>& keypoints) {
  ByteWriter w(keypoints.size() * kKeypointBytes);
  for (const cv::KeyPoint& k : keypoints) {
    w.put<float>(k.pt.x);
    w.put<float>(k.pt.y);
    w.put<float>(k.size);
    w.put<float>(k.angle);
    w.put<float>(k.response);
    w.put<int32_t>(k.octave);
    w.put<int32_t>(k.class_id);
  }
  return w.take();
}

std::vector<cv::KeyPoint> decodeKeypoints(const unsigned char* data, size_t size) {
  requireMultiple(size, kKeypointBytes, "keypoints");
  ByteReader r(data, size, "keypoints");
  std::vector<cv::KeyPoint> keypoints(size / kKeypointBytes);
  for (cv::KeyPoint& k : keypoints) {
    k.pt.x = r.get<float>();
    k.pt.y = r.get<float>();
    k.size = r.get<float>();
    k.angle = r.get<float>();
    k.response = r.get<float>();
    k.octave = r.get<int32_t>();
    k.class_id = r.get<int32_t>();
  }
  return keypoints;
}

Bytes encodePoints(const std::vector<cv::Point3f>& points) {
  static_assert(sizeof(cv::Point3f) == 3 * sizeof(float), "cv::Point3f is packed");
  return encodeArray(points);
}

std::vector<cv::Point3f> decodePoints(const unsigned char* data, size_t size) {
  return decodeArray<cv::Point3f>(data, size, "3D points");
}

Bytes encodeMatrix(const cv::Mat& matrix) {
  if (matrix.empty()) return {};
  if (matrix.dims != 2) throw FormatError("only 2D matrices can be stored");
  const size_t rowBytes = matrix.cols * matrix.elemSize();
  ByteWriter w(12 + rowBytes * matrix.rows);
  w.put<int32_t>(matrix.type());
  w.put<int32_t>(matrix.rows);
  w.put<int32_t>(matrix.cols);
  for (int i = 0; i < matrix.rows; ++i) w.putBytes(matrix.ptr(i), rowBytes);
  return w.take();
}

cv::Mat decodeMatrix(const unsigned char* data, size_t size) {
  if (size == 0) return cv::Mat();
  ByteReader r(data, size, "matrix");
  const int32_t type = r.get<int32_t>();
  const int32_t rows = r.get<int32_t>();
  const int32_t cols = r.get<int32_t>();
  if (rows <= 0 || cols <= 0 || CV_MAT_DEPTH(type) > CV_16F) {
    throw FormatError("stored matrix has a bad header (type " + std::to_string(type) + ", " +
                      std::to_string(rows) + "x" + std::to_string(cols) + ")");
  }
  const size_t bytes = static_cast<size_t>(rows) * cols * CV_ELEM_SIZE(type);
  const unsigned char* payload = r.take(bytes);
  r.expectEnd();
  cv::Mat matrix(rows, cols, type);
  std::memcpy(matrix.data, payload, bytes);
  return matrix;
}

Bytes encodeStatistics(const std::map<std::string, float>& data) {
  std::string text;
  char value[32];
  for (const auto& [key, v] : data) {
    // %.9g round-trips every float exactly.
    std::snprintf(value, sizeof(value), "%.9g", static_cast<double>(v));
    text += key;
    text += ' ';
    text += value;
    text += '\n';
  }
  return codec::compressBytes(Bytes(text.begin(), text.end()));
}

std::map<std::string, float> decodeStatistics(const unsigned char* data, size_t size) {
  std::map<std::string, float> statistics;
  if (size == 0) return statistics;
  const Bytes raw = codec::uncompressBytes(Bytes(data, data + size));
  std::istringstream lines(std::string(raw.begin(), raw.end()));
  std::string line;
  while (std::getline(lines, line)) {
    const size_t space = line.rfind(' ');
    if (space == std::string::npos) throw FormatError("stored statistics line \"" + line + "\" has no value");
    // strtof reads nan and inf, which statistics may legitimately hold.
    statistics[line.substr(0, space)] = std::strtof(line.c_str() + space + 1, nullptr);
  }
  return statistics;
}

Bytes encodeIds(const std::vector<int>& ids) {
  if (ids.empty()) return {};
  return codec::compressBytes(encodeWordIds(ids));
}

std::vector<int> decodeIds(const unsigned char* data, size_t size) {
  if (size == 0) return {};
  const Bytes raw = codec::uncompressBytes(Bytes(data, data + size));
  return decodeWordIds(raw.data(), raw.size());
}

}  // namespace rtabmap::db::blob

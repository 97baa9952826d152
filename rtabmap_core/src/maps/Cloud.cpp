#include "rtabmap_core/maps/Cloud.h"

#include <cstring>
#include <string>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {

void Cloud::reserve(size_t n, bool withColors) {
  points.reserve(n);
  if (withColors) colors.reserve(n);
}

void Cloud::append(const Cloud& other) {
  if (other.empty()) return;
  const bool keepColors = (empty() || hasColors()) && other.hasColors();
  if (!keepColors) colors.clear();
  points.insert(points.end(), other.points.begin(), other.points.end());
  if (keepColors) colors.insert(colors.end(), other.colors.begin(), other.colors.end());
}

Cloud transformCloud(const Cloud& cloud, const Transform& t) {
  Cloud out;
  out.colors = cloud.colors;
  out.points.resize(cloud.points.size());
  const Eigen::Matrix4f m = t.toMatrix4d().cast<float>();
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const cv::Point3f& p = cloud.points[i];
    out.points[i] = cv::Point3f(m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2) * p.z + m(0, 3),
                                m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2) * p.z + m(1, 3),
                                m(2, 0) * p.x + m(2, 1) * p.y + m(2, 2) * p.z + m(2, 3));
  }
  return out;
}

float packRgb(const cv::Vec3b& rgb) {
  const uint32_t bits = (uint32_t(rgb[0]) << 16) | (uint32_t(rgb[1]) << 8) | uint32_t(rgb[2]);
  float f;
  std::memcpy(&f, &bits, sizeof(f));
  return f;
}

cv::Vec3b unpackRgb(float packed) {
  uint32_t bits;
  std::memcpy(&bits, &packed, sizeof(bits));
  return cv::Vec3b((bits >> 16) & 0xff, (bits >> 8) & 0xff, bits & 0xff);
}

cv::Mat cellsFromCloud(const Cloud& cloud, bool is2D) {
  if (cloud.empty()) return cv::Mat();
  const int n = static_cast<int>(cloud.size());
  if (is2D) {
    cv::Mat cells(1, n, CV_32FC2);
    auto* out = cells.ptr<cv::Vec2f>();
    for (int i = 0; i < n; ++i) out[i] = cv::Vec2f(cloud.points[i].x, cloud.points[i].y);
    return cells;
  }
  if (cloud.hasColors()) {
    cv::Mat cells(1, n, CV_32FC4);
    auto* out = cells.ptr<cv::Vec4f>();
    for (int i = 0; i < n; ++i) {
      const cv::Point3f& p = cloud.points[i];
      out[i] = cv::Vec4f(p.x, p.y, p.z, packRgb(cloud.colors[i]));
    }
    return cells;
  }
  cv::Mat cells(1, n, CV_32FC3);
  std::memcpy(cells.data, cloud.points.data(), sizeof(cv::Point3f) * n);
  return cells;
}

bool isCellMatrix(const cv::Mat& cells) {
  if (cells.empty()) return true;
  const int type = cells.type();
  return (type == CV_32FC2 || type == CV_32FC3 || type == CV_32FC4) &&
         (cells.rows == 1 || cells.cols == 1);
}

Cloud cloudFromCells(const cv::Mat& cellsIn) {
  Cloud cloud;
  if (cellsIn.empty()) return cloud;
  if (!isCellMatrix(cellsIn)) {
    throw FormatError("local grid cells must be a 1xN or Nx1 CV_32FC2, CV_32FC3 or CV_32FC4 "
                      "matrix (got " + std::to_string(cellsIn.rows) + "x" +
                      std::to_string(cellsIn.cols) + " with " +
                      std::to_string(cellsIn.channels()) + " channels of depth " +
                      std::to_string(cellsIn.depth()) + ")");
  }
  const cv::Mat cells = cellsIn.isContinuous() ? cellsIn : cellsIn.clone();
  const int n = static_cast<int>(cells.total());
  const int ch = cells.channels();
  const float* f = cells.ptr<float>();
  cloud.points.resize(n);
  if (ch == 4) cloud.colors.resize(n);
  for (int i = 0; i < n; ++i, f += ch) {
    cloud.points[i] = cv::Point3f(f[0], f[1], ch >= 3 ? f[2] : 0.0f);
    if (ch == 4) cloud.colors[i] = unpackRgb(f[3]);
  }
  return cloud;
}

}  // namespace rtabmap

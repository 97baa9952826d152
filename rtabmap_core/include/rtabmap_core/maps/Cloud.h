#pragma once
// A point cloud as the map stages pass it around: points (metres) and, optionally, one RGB
// colour per point. A plain type on purpose: PCL stays inside the .cpp files that need it, so
// including this costs nothing and the ROS layer can fill it from a PointCloud2 directly.
//
// LocalGrid cells (geometry/SensorData.h) are stored as 1xN float matrices: CV_32FC2 (x y, a
// 2D grid), CV_32FC3 (x y z) or CV_32FC4 (x y z rgb, the colour packed into the float's bits
// as 0x00RRGGBB, as LaserScan::kXYZRGB and PCL do). cellsFromCloud / cloudFromCells convert.
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include <cstddef>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

struct Cloud {
  std::vector<cv::Point3f> points;
  std::vector<cv::Vec3b> colors;  // empty, or one per point, in R G B order

  size_t size() const { return points.size(); }
  bool empty() const { return points.empty(); }
  bool hasColors() const { return !colors.empty() && colors.size() == points.size(); }
  void reserve(size_t n, bool withColors);
  void push_back(const cv::Point3f& p) { points.push_back(p); }
  void push_back(const cv::Point3f& p, const cv::Vec3b& c) {
    points.push_back(p);
    colors.push_back(c);
  }
  // Appends another cloud; colours are kept only if both clouds have them (or this one is
  // empty).
  void append(const Cloud& other);
};

// Every point transformed by t (t * p).
Cloud transformCloud(const Cloud& cloud, const Transform& t);

// Cells of a local grid from a cloud: CV_32FC2 when is2D (z dropped), else CV_32FC3, or
// CV_32FC4 when the cloud has colours (and !is2D). Empty cloud -> empty matrix.
cv::Mat cellsFromCloud(const Cloud& cloud, bool is2D);
// Inverse: any of the formats above (z = 0 for CV_32FC2). Throws FormatError for another
// type, naming it.
Cloud cloudFromCells(const cv::Mat& cells);
// True for the cell formats above (or an empty matrix).
bool isCellMatrix(const cv::Mat& cells);

// Packing of a colour into a float, as LaserScan::kXYZRGB (0x00RRGGBB bit pattern).
float packRgb(const cv::Vec3b& rgb);
cv::Vec3b unpackRgb(float packed);

}  // namespace rtabmap

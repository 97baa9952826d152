#pragma once
// A 2D occupancy map as navigation consumes it, with nav_msgs/OccupancyGrid semantics, so the
// ROS layer copies it into the message as is:
//  - data: CV_8SC1, rows = height, cols = width, row-major starting at the origin cell: row 0
//    is the lowest y, column 0 the lowest x (an image of it is upside down: flip it to view);
//    values -1 unknown, 0 free, 100 occupied;
//  - resolution: metres per cell;
//  - originX, originY: world position of the corner of cell (0, 0) (the message's
//    info.origin.position; orientation identity).
#include <opencv2/core/mat.hpp>

#include <cstdint>

namespace rtabmap {

struct GridMap {
  static constexpr int8_t kUnknown = -1;
  static constexpr int8_t kFree = 0;
  static constexpr int8_t kOccupied = 100;

  cv::Mat data;  // CV_8SC1
  float resolution = 0.0f;
  double originX = 0.0;
  double originY = 0.0;

  bool empty() const { return data.empty(); }
  int width() const { return data.cols; }
  int height() const { return data.rows; }
  // Value of the cell holding world point (x, y); kUnknown outside the map.
  int8_t at(double x, double y) const;
  // Cell of a world point; false when outside.
  bool cellOf(double x, double y, int& col, int& row) const;
  // Counts of each value.
  int countFree() const;
  int countOccupied() const;
  int countUnknown() const;
};

}  // namespace rtabmap

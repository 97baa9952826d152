#include "rtabmap_core/maps/GridMap.h"

#include <cmath>

namespace rtabmap {

bool GridMap::cellOf(double x, double y, int& col, int& row) const {
  if (data.empty() || !(resolution > 0.0f)) return false;
  col = static_cast<int>(std::floor((x - originX) / resolution));
  row = static_cast<int>(std::floor((y - originY) / resolution));
  return col >= 0 && row >= 0 && col < data.cols && row < data.rows;
}

int8_t GridMap::at(double x, double y) const {
  int col, row;
  if (!cellOf(x, y, col, row)) return kUnknown;
  return data.at<int8_t>(row, col);
}

namespace {
int countValue(const cv::Mat& data, int8_t value) {
  int n = 0;
  for (int r = 0; r < data.rows; ++r) {
    const int8_t* p = data.ptr<int8_t>(r);
    for (int c = 0; c < data.cols; ++c) n += p[c] == value;
  }
  return n;
}
}  // namespace

int GridMap::countFree() const { return countValue(data, kFree); }
int GridMap::countOccupied() const { return countValue(data, kOccupied); }
int GridMap::countUnknown() const { return countValue(data, kUnknown); }

}  // namespace rtabmap

#pragma once
// The cells of one node's local grid as the global 2D grid caches them for the whole map (every
// node, Long-Term Memory included: a re-assembly replays them), so their bytes per node are what
// the map costs per node. Internal to the maps area.
//
// Ray-traced free space is a set of cell centres of the local lattice, (i + 0.5) * cellSize, on
// the plane z = 0 (ScanRayTracing, projectTo2D): it is kept as runs along x of consecutive cells,
// (row, first col, length) in 6 bytes, a few KB for the thousands of cells of a 30 m laser scan
// (12 bytes a cell as float x y z). Any other set (obstacle means, 3D cells, a grid of another
// maker) keeps its floats, without z when every z is 0. Decoding gives back the same float bits
// as the input (checked when encoding: a cell that would not round-trip exactly keeps the
// float form), so every path of the map writes exactly the cells the floats would.
#include <opencv2/core/types.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rtabmap::maps_detail {

constexpr int kChunk = 256;  // cells per decoded batch

class CellSet {
 public:
  CellSet() = default;
  CellSet(const std::vector<cv::Point3f>& points, float cellSize);

  size_t count() const { return count_; }
  bool empty() const { return count_ == 0; }
  bool runLength() const { return !runs_.empty(); }
  size_t bytes() const;  // heap bytes held

  // Calls f(x, y, z, n) on consecutive batches of at most kChunk cells (float arrays), every
  // cell once. The order is the input's for the float form, by row then column for runs; a cell
  // given twice in a lattice set comes once (a node updates a cell at most once anyway).
  template <class F>
  void forEachBatch(F&& f) const {
    forEachBatch(f, [](const cv::Point2f&, const cv::Point2f&) { return true; });
  }
  // Same, skipping the runs for which keepRun(first cell, last cell) (their centres) is false:
  // a re-assembly that writes only a few tiles need not project the cells of runs far from
  // them. The float form has no runs: every cell is given.
  template <class F, class KeepRun>
  void forEachBatch(F&& f, KeepRun&& keepRun) const;

 private:
  struct Run {
    int16_t row, col;  // first cell of the run on the local lattice
    uint16_t length;
  };
  bool encodeRuns(const std::vector<cv::Point3f>& points);

  float cellSize_ = 0.0f;
  size_t count_ = 0;
  std::vector<Run> runs_;
  std::vector<float> x_, y_, z_;  // float form; z_ empty when every z is 0
};

template <class F, class KeepRun>
void CellSet::forEachBatch(F&& f, KeepRun&& keepRun) const {
  static const float kZeros[kChunk] = {};
  if (runs_.empty()) {
    for (size_t start = 0; start < count_; start += kChunk) {
      const int m = static_cast<int>(std::min<size_t>(kChunk, count_ - start));
      f(&x_[start], &y_[start], z_.empty() ? kZeros : &z_[start], m);
    }
    return;
  }
  float x[kChunk], y[kChunk];
  int m = 0;
  for (const Run& r : runs_) {
    const float yc = (static_cast<float>(r.row) + 0.5f) * cellSize_;
    if (!keepRun(cv::Point2f((static_cast<float>(r.col) + 0.5f) * cellSize_, yc),
                 cv::Point2f((static_cast<float>(r.col + r.length - 1) + 0.5f) * cellSize_, yc))) {
      continue;
    }
    for (int k = 0; k < r.length; ++k) {
      x[m] = (static_cast<float>(r.col + k) + 0.5f) * cellSize_;  // Raster2D's cellCentre
      y[m] = yc;
      if (++m == kChunk) {
        f(x, y, kZeros, m);
        m = 0;
      }
    }
  }
  if (m > 0) f(x, y, kZeros, m);
}

}  // namespace rtabmap::maps_detail

#pragma once
// A small dense raster of cell states over a bounding box of the local lattice
// floor(coordinate / cellSize), for 2D ray tracing of one local grid. Internal to the maps area.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace rtabmap::maps_detail {

// Cell index of a coordinate on the lattice shared by local and global grids.
inline int cellIndex(float v, float cellSize) { return static_cast<int>(std::floor(v / cellSize)); }
inline float cellCentre(int i, float cellSize) { return (static_cast<float>(i) + 0.5f) * cellSize; }

class Raster2D {
 public:
  enum State : uint8_t { kUnknown = 0, kFree = 1, kGround = 2, kObstacle = 3 };

  // Inclusive cell bounds.
  Raster2D(int minCol, int minRow, int maxCol, int maxRow)
      : minCol_(minCol), minRow_(minRow), width_(maxCol - minCol + 1), height_(maxRow - minRow + 1),
        cells_(static_cast<size_t>(width_) * height_, kUnknown) {}

  int minCol() const { return minCol_; }
  int minRow() const { return minRow_; }
  int width() const { return width_; }
  int height() const { return height_; }
  bool inside(int col, int row) const {
    return col >= minCol_ && row >= minRow_ && col < minCol_ + width_ && row < minRow_ + height_;
  }
  uint8_t get(int col, int row) const { return cells_[offset(col, row)]; }
  void set(int col, int row, uint8_t s) { cells_[offset(col, row)] = s; }
  // Raises a cell's state (unknown < free < ground < obstacle): what a cell is seen as most
  // strongly in this grid wins.
  void raise(int col, int row, uint8_t s) {
    uint8_t& c = cells_[offset(col, row)];
    if (s > c) c = s;
  }
  const std::vector<uint8_t>& cells() const { return cells_; }

  // Bresenham line from (c0, r0) to (c1, r1); every cell on it becomes at least free, the end
  // cell only if includeEnd. Cells already ground or obstacle keep their state: a ray of the same
  // grid never clears what this grid saw occupied (a grazing beam may cross a hit cell). With
  // stopAtObstacle, the ray ends at the first obstacle cell on its way.
  void traceFree(int c0, int r0, int c1, int r1, bool includeEnd, bool stopAtObstacle = false) {
    const int dc = std::abs(c1 - c0), dr = -std::abs(r1 - r0);
    const int sc = c0 < c1 ? 1 : -1, sr = r0 < r1 ? 1 : -1;
    int err = dc + dr;
    int c = c0, r = r0;
    while (true) {
      const bool atEnd = (c == c1 && r == r1);
      if (atEnd && !includeEnd) break;
      if (stopAtObstacle && get(c, r) == kObstacle) break;
      raise(c, r, kFree);
      if (atEnd) break;
      const int e2 = 2 * err;
      if (e2 >= dr) { err += dr; c += sc; }
      if (e2 <= dc) { err += dc; r += sr; }
    }
  }

 private:
  size_t offset(int col, int row) const {
    return static_cast<size_t>(row - minRow_) * width_ + (col - minCol_);
  }
  int minCol_, minRow_, width_, height_;
  std::vector<uint8_t> cells_;
};

// Accumulates the points falling in each cell to emit one point per cell: their mean.
struct CellMean {
  int64_t key;
  float x, y, z;
  int count;
};
// UBSan fix (make test-asan): shifting a negative row left is undefined before C++20; shift
// its unsigned two's-complement image instead (same key bits).
inline int64_t cellKey(int col, int row) {
  return static_cast<int64_t>(static_cast<uint64_t>(static_cast<int64_t>(row)) << 32) ^
         static_cast<int64_t>(static_cast<uint32_t>(col));
}

}  // namespace rtabmap::maps_detail

#pragma once
// The cells of the global 2D grid and the operations the assembly paths are made of: apply a
// node's cells at a pose (log-odds, one update per node and cell), clear tiles, footprint counts,
// growth. Internal to the maps area (OccupancyGrid.cpp owns the policy).
//
// Storage: cell (col0 + i, row0 + j) of the world lattice floor(coordinate / cellSize) at index
// j * width + i. col0 and row0 are multiples of the tile size, so a world tile (32 x 32 cells,
// floor(col / 32), floor(row / 32)) is always one storage tile.
#include <opencv2/core/types.hpp>

#include <climits>
#include <cstdint>
#include <memory>
#include <vector>

#include "Cells.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/maps/GridMap.h"

namespace rtabmap::maps_detail {

constexpr float kUnknownLogOdds = -1.0e9f;  // what logOddsAt() returns for an unknown cell
// Log-odds are stored in fixed point, thousandths: a cell is 4 bytes with its stamp, so twice
// as many cells stay in cache as with a float and a 32-bit stamp, and sums are exact integers.
constexpr float kLogOddsScale = 1000.0f;
constexpr int16_t kUnknownFixed = INT16_MIN;
constexpr int kTileShift = 5;
constexpr int kTile = 1 << kTileShift;
constexpr int kTileCells = kTile * kTile;

// Long-Term Memory layers (see OccupancyGrid.h). A node's layer key: the serial of its eviction
// from the Working Memory, or kInWorkingMemory. A tile gate: a node writes a cell of a tile being
// re-assembled iff its key >= the tile's gate; a layer captured at serial c holds the nodes with
// a key below c, so its tile's gate is c. kGateClosed: the tile is not being re-assembled.
constexpr uint32_t kGateClosed = UINT32_MAX;
constexpr uint32_t kInWorkingMemory = UINT32_MAX - 1;
constexpr uint32_t kGateOpen = 0;

inline int fastFloor(float v) {
  const int i = static_cast<int>(v);
  return i - (v < static_cast<float>(i));
}

// Inclusive cell bounds on the world lattice.
struct CellBox {
  int c0 = 0, r0 = 0, c1 = -1, r1 = -1;
  bool empty() const { return c1 < c0 || r1 < r0; }
  void unite(const CellBox& b);
};

// World tile key of a world cell.
// UBSan fix (make test-asan): shifting a negative row left is undefined before C++20; shift
// its unsigned two's-complement image instead (same key bits).
inline int64_t tileKeyOfTile(int tileCol, int tileRow) {
  return static_cast<int64_t>(static_cast<uint64_t>(static_cast<int64_t>(tileRow)) << 32) ^
         static_cast<int64_t>(static_cast<uint32_t>(tileCol));
}
inline int64_t tileKey(int col, int row) { return tileKeyOfTile(col >> kTileShift, row >> kTileShift); }
inline int tileCol(int64_t key) { return static_cast<int32_t>(static_cast<uint32_t>(key & 0xffffffff)); }
inline int tileRow(int64_t key) { return static_cast<int32_t>(key >> 32); }

// A node's cells in its base frame (compact, see Cells.h): obstacles are applied first, then
// free cells (ground, and the empty cells of a 2D grid). An evicted node (out of the Working
// Memory) keeps only what deciding a re-assembly needs: its bounds, radius and cell count; its
// cells come back through the grid's loader when a re-assembly applies it. The cell sets live
// behind one pointer so that an evicted node, kept for every node of the map, costs a few tens of
// bytes and not the two sets' empty shells.
struct NodeCells {
  struct Sets {
    CellSet obstacles, free;
  };
  std::shared_ptr<const Sets> sets;  // null: evicted (or no cells given)
  cv::Point3f lo{0, 0, 0}, hi{0, 0, 0};
  float radius = 0.0f;  // farthest cell from the node's origin, in the plane
  size_t cells = 0;     // obstacles + free cells, kept when evicted
  uint32_t layerKey = kInWorkingMemory;  // see kGateClosed

  NodeCells() = default;
  NodeCells(const std::vector<cv::Point3f>& obstacleCells, const std::vector<cv::Point3f>& freeCells,
            float cellSize);
  size_t count() const { return cells; }
  bool evicted() const { return !sets; }
  const CellSet& obstacles() const { return sets ? sets->obstacles : kNoCells; }
  const CellSet& free() const { return sets ? sets->free : kNoCells; }
  size_t bytes() const {
    return sizeof(NodeCells) + (sets ? sizeof(Sets) + sets->obstacles.bytes() + sets->free.bytes() : 0);
  }
  void evict() { sets.reset(); }

 private:
  static const CellSet kNoCells;
};

// The world tiles a node's cells fall in at the pose it is assembled at, kept for every node of
// the map (Long-Term Memory included) to tell which nodes a re-assembled tile needs: runs of
// consecutive tiles along a row, 12 bytes a run, where a node's cells cover a few rows of tiles
// each with several consecutive ones (8 bytes a tile as a list of keys).
class TileSet {
 public:
  TileSet() = default;
  explicit TileSet(const std::vector<int64_t>& sortedKeys);  // sorted as int64_t, no duplicates

  // f(key) for every tile, in the order of the keys given.
  template <class F>
  void forEach(F&& f) const {
    for (const Run& r : runs_) {
      for (int32_t k = 0; k < r.length; ++k) f(tileKeyOfTile(r.col + k, r.row));
    }
  }
  template <class P>
  bool any(P&& p) const {
    for (const Run& r : runs_) {
      for (int32_t k = 0; k < r.length; ++k) {
        if (p(tileKeyOfTile(r.col + k, r.row))) return true;
      }
    }
    return false;
  }
  std::vector<int64_t> keys() const;
  size_t runs() const { return runs_.size(); }
  size_t bytes() const { return runs_.capacity() * sizeof(Run); }

 private:
  struct Run {
    int32_t row, col, length;  // tile coordinates of the first tile
  };
  std::vector<Run> runs_;
};

class GridStorage {
 public:
  GridStorage(float cellSize, float hit, float miss, float clampMin, float clampMax, bool footprint);

  // Conservative bounds of a node's cells at a pose (and of a footprint disk).
  CellBox boxAt(const NodeCells& n, const Transform& pose) const;
  CellBox diskBox(const Transform& pose, float radius) const;
  // The world tiles a node's cells fall in at a pose, sorted.
  std::vector<int64_t> tilesAt(const NodeCells& n, const Transform& pose) const;

  bool empty() const { return cells_.empty(); }
  void reset(const CellBox& b);      // fresh storage covering b (all unknown)
  void ensureCovers(const CellBox& b);  // grows, keeping the content
  void release();

  // Applies a node. With `masked`, only cells of dirty tiles whose gate is at most `key` are
  // written. `tiles` (optional) receives the world tiles its cells were written in, sorted.
  // Returns the cell updates made.
  long apply(const NodeCells& n, const Transform& pose, bool masked, std::vector<int64_t>* tiles,
             uint32_t key = kInWorkingMemory);
  void addFootprint(const Transform& pose, float radius, int sign);

  // Dirty tiles (being re-assembled): a gate other than kGateClosed.
  void clearDirty();                 // every gate closed
  void markDirty(int64_t worldTile);  // gate open, unless already dirty
  void markDirty(const CellBox& b);
  void markAllDirty();
  bool isDirty(int64_t worldTile) const;
  uint32_t gate(int64_t worldTile) const { return tileInside(worldTile) ? gate_[tileIndex(worldTile)] : kGateClosed; }
  void setGate(int64_t worldTile, uint32_t gate);  // of a dirty tile
  long dirtyTiles() const;
  long tiles() const { return static_cast<long>(gate_.size()); }
  std::vector<int64_t> dirtyTileKeys() const;
  void clearDirtyCells();  // sets the cells of dirty tiles unknown
  // A tile's log-odds (kTileCells, row-major; kUnknownFixed unknown) out of and into storage.
  void captureTile(int64_t worldTile, std::vector<int16_t>& out) const;
  void restoreTile(int64_t worldTile, const std::vector<int16_t>& in);

  // -1 / 0 / 100 over the known bounds, padded to minCells, footprint and erosion applied.
  GridMap toMap(float thresholdFixed, int minCells, bool eroded) const;  // threshold in thousandths
  float logOddsAt(double x, double y) const;  // kUnknownLogOdds when unknown or outside
  long area() const { return static_cast<long>(width_) * height_; }
  size_t bytes() const;

 private:
  size_t tileIndex(int64_t worldTile) const;
  bool tileInside(int64_t worldTile) const;

  float cellSize_;
  int16_t hit_, miss_, min_, max_;  // fixed point
  bool footprint_;
  int col0_ = 0, row0_ = 0, width_ = 0, height_ = 0;
  int tilesW_ = 0, tilesH_ = 0;
  // A cell's log-odds and the serial of the last node that wrote it (one update per node and
  // cell), side by side: a cell update touches one cache line, not two.
  struct Cell {
    int16_t logOdds = kUnknownFixed;
    uint16_t stamp = 0;
  };
  std::vector<Cell> cells_;
  uint16_t serial_ = 0;
  std::vector<uint16_t> footprint_counts_;  // nodes whose footprint disk covers the cell
  std::vector<uint32_t> gate_;  // per storage tile
};

}  // namespace rtabmap::maps_detail

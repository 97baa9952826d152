// Compact cells of a node's local grid (see Cells.h).
#include "Cells.h"

#include <cmath>
#include <cstring>
#include <limits>

namespace rtabmap::maps_detail {

namespace {

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

// The lattice index of a coordinate that is exactly the centre (i + 0.5) * cellSize of cell i
// (the expression of Raster2D's cellCentre, so the same bits), or false.
bool latticeIndex(float v, float cellSize, int& i) {
  const float q = std::floor(v / cellSize);
  if (!(std::fabs(q) < 32000.0f)) return false;  // int16 with room for a run's length
  i = static_cast<int>(q);
  return sameBits((static_cast<float>(i) + 0.5f) * cellSize, v);
}

}  // namespace

CellSet::CellSet(const std::vector<cv::Point3f>& points, float cellSize) : cellSize_(cellSize) {
  if (points.empty()) return;
  if (cellSize > 0.0f && encodeRuns(points)) return;
  count_ = points.size();
  x_.reserve(count_);
  y_.reserve(count_);
  bool flat = true;
  for (const cv::Point3f& p : points) {
    x_.push_back(p.x);
    y_.push_back(p.y);
    flat = flat && p.z == 0.0f;
  }
  if (!flat) {
    z_.reserve(count_);
    for (const cv::Point3f& p : points) z_.push_back(p.z);
  }
}

bool CellSet::encodeRuns(const std::vector<cv::Point3f>& points) {
  // A cell as one 32-bit key ordered by row then column (both within int16, latticeIndex): a
  // node read back from the database is encoded again, and sorting these is what that costs.
  constexpr int kBias = 1 << 15;
  std::vector<uint32_t> cells;
  cells.reserve(points.size());
  for (const cv::Point3f& p : points) {
    int c = 0, r = 0;
    if (p.z != 0.0f || !latticeIndex(p.x, cellSize_, c) || !latticeIndex(p.y, cellSize_, r)) return false;
    cells.push_back(static_cast<uint32_t>(r + kBias) << 16 | static_cast<uint32_t>(c + kBias));
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  std::vector<Run> runs;
  for (const uint32_t key : cells) {
    const int r = static_cast<int>(key >> 16) - kBias, c = static_cast<int>(key & 0xffffu) - kBias;
    if (!runs.empty() && runs.back().row == r && runs.back().col + runs.back().length == c &&
        runs.back().length < std::numeric_limits<uint16_t>::max()) {
      ++runs.back().length;
    } else {
      runs.push_back({static_cast<int16_t>(r), static_cast<int16_t>(c), 1});
    }
  }
  // Scattered cells (a sparse set) would take more as runs than as floats.
  if (runs.size() * sizeof(Run) >= cells.size() * 2 * sizeof(float)) return false;
  runs.shrink_to_fit();
  runs_ = std::move(runs);
  count_ = cells.size();
  return true;
}

size_t CellSet::bytes() const {
  return runs_.capacity() * sizeof(Run) + (x_.capacity() + y_.capacity() + z_.capacity()) * sizeof(float);
}

}  // namespace rtabmap::maps_detail

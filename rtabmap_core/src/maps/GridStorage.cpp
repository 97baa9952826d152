#include "GridStorage.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rtabmap::maps_detail {

namespace {

// The x and y rows of a pose, in float: what projecting a cell needs.
struct Affine {
  float r00, r01, r02, tx, r10, r11, r12, ty;
  explicit Affine(const Transform& t) {
    const Eigen::Matrix4d m = t.toMatrix4d();
    r00 = float(m(0, 0)); r01 = float(m(0, 1)); r02 = float(m(0, 2)); tx = float(m(0, 3));
    r10 = float(m(1, 0)); r11 = float(m(1, 1)); r12 = float(m(1, 2)); ty = float(m(1, 3));
  }
  float x(const cv::Point3f& p) const { return r00 * p.x + r01 * p.y + r02 * p.z + tx; }
  float y(const cv::Point3f& p) const { return r10 * p.x + r11 * p.y + r12 * p.z + ty; }
};

// World cells of a batch of a node's cells at a pose: one function for every caller, so that the
// tiles a node is recorded in and the cells it writes agree to the last bit. Written so that the
// compiler vectorises it (x86-64 has no fused multiply-add here: vector and scalar iterations
// round alike).
struct CellProjector {
  float ax, bx, cx, dx, ay, by, cy, dy;
  CellProjector(const Transform& pose, float cellSize) {
    const Affine a(pose);
    const float inv = 1.0f / cellSize;
    ax = a.r00 * inv; bx = a.r01 * inv; cx = a.r02 * inv; dx = a.tx * inv;
    ay = a.r10 * inv; by = a.r11 * inv; cy = a.r12 * inv; dy = a.ty * inv;
  }
  void project(const float* x, const float* y, const float* z, int n, int* cols, int* rows) const {
    for (int k = 0; k < n; ++k) {
      const float fx = ax * x[k] + bx * y[k] + cx * z[k] + dx;
      const float fy = ay * x[k] + by * y[k] + cy * z[k] + dy;
      const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
      cols[k] = ix - (fx < static_cast<float>(ix));
      rows[k] = iy - (fy < static_cast<float>(iy));
    }
  }
};

int floorTo(int v, int multiple) { return (v >= 0 ? v / multiple : -((-v + multiple - 1) / multiple)) * multiple; }

void sortUnique(std::vector<int64_t>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

}  // namespace

NodeCells::NodeCells(const std::vector<cv::Point3f>& obstacleCells, const std::vector<cv::Point3f>& freeCells,
                     float cellSize)
    : sets(std::make_shared<const Sets>(Sets{CellSet(obstacleCells, cellSize), CellSet(freeCells, cellSize)})) {
  cells = sets->obstacles.count() + sets->free.count();
  bool first = true;
  for (const auto* cells : {&obstacleCells, &freeCells}) {
    for (const cv::Point3f& p : *cells) {
      if (first) {
        lo = hi = p;
        first = false;
      }
      lo.x = std::min(lo.x, p.x); lo.y = std::min(lo.y, p.y); lo.z = std::min(lo.z, p.z);
      hi.x = std::max(hi.x, p.x); hi.y = std::max(hi.y, p.y); hi.z = std::max(hi.z, p.z);
      radius = std::max(radius, std::sqrt(p.x * p.x + p.y * p.y));
    }
  }
}

const CellSet NodeCells::kNoCells;

TileSet::TileSet(const std::vector<int64_t>& sortedKeys) {
  std::vector<Run> runs;
  for (int64_t key : sortedKeys) {
    const int col = tileCol(key), row = tileRow(key);
    if (runs.empty() || runs.back().row != row || runs.back().col + runs.back().length != col) {
      runs.push_back(Run{row, col, 0});
    }
    ++runs.back().length;
  }
  runs_.assign(runs.begin(), runs.end());  // exactly their bytes: kept for every node of the map
}

std::vector<int64_t> TileSet::keys() const {
  std::vector<int64_t> out;
  forEach([&](int64_t k) { out.push_back(k); });
  return out;
}

void CellBox::unite(const CellBox& b) {
  if (b.empty()) return;
  if (empty()) {
    *this = b;
    return;
  }
  c0 = std::min(c0, b.c0); r0 = std::min(r0, b.r0);
  c1 = std::max(c1, b.c1); r1 = std::max(r1, b.r1);
}

namespace {
int16_t toFixed(float logOdds) {
  return static_cast<int16_t>(std::lround(std::max(-30.0f, std::min(30.0f, logOdds)) * kLogOddsScale));
}
}  // namespace

GridStorage::GridStorage(float cellSize, float hit, float miss, float clampMin, float clampMax, bool footprint)
    : cellSize_(cellSize), hit_(toFixed(hit)), miss_(toFixed(miss)), min_(toFixed(clampMin)),
      max_(toFixed(clampMax)), footprint_(footprint) {}

CellBox GridStorage::boxAt(const NodeCells& n, const Transform& pose) const {
  // The cells lie in the box of the 8 local corners: their image bounds the cells.
  const Affine a(pose);
  float x0 = std::numeric_limits<float>::max(), x1 = -x0, y0 = x0, y1 = -x0;
  for (int k = 0; k < 8; ++k) {
    const cv::Point3f p((k & 1) ? n.hi.x : n.lo.x, (k & 2) ? n.hi.y : n.lo.y, (k & 4) ? n.hi.z : n.lo.z);
    x0 = std::min(x0, a.x(p)); x1 = std::max(x1, a.x(p));
    y0 = std::min(y0, a.y(p)); y1 = std::max(y1, a.y(p));
  }
  const float inv = 1.0f / cellSize_;
  // One cell of slack on each side absorbs float rounding at the borders.
  return CellBox{fastFloor(x0 * inv) - 1, fastFloor(y0 * inv) - 1, fastFloor(x1 * inv) + 1, fastFloor(y1 * inv) + 1};
}

CellBox GridStorage::diskBox(const Transform& pose, float r) const {
  const float inv = 1.0f / cellSize_;
  const float x = float(pose.x()), y = float(pose.y());
  return CellBox{fastFloor((x - r) * inv), fastFloor((y - r) * inv), fastFloor((x + r) * inv), fastFloor((y + r) * inv)};
}

std::vector<int64_t> GridStorage::tilesAt(const NodeCells& n, const Transform& pose) const {
  const CellProjector proj(pose, cellSize_);
  std::vector<int64_t> tiles;
  int cols[kChunk], rows[kChunk];
  int64_t last = std::numeric_limits<int64_t>::min();
  for (const CellSet* set : {&n.obstacles(), &n.free()}) {
    set->forEachBatch([&](const float* x, const float* y, const float* z, int m) {
      proj.project(x, y, z, m, cols, rows);
      for (int k = 0; k < m; ++k) {
        const int64_t t = tileKey(cols[k], rows[k]);
        if (t != last) tiles.push_back(last = t);  // neighbouring cells mostly share a tile
      }
    });
  }
  sortUnique(tiles);
  return tiles;
}

void GridStorage::reset(const CellBox& b) {
  const int margin = kTile;
  col0_ = floorTo(b.c0 - margin, kTile);
  row0_ = floorTo(b.r0 - margin, kTile);
  width_ = floorTo(b.c1 + margin, kTile) + kTile - col0_;
  height_ = floorTo(b.r1 + margin, kTile) + kTile - row0_;
  const size_t n = size_t(width_) * height_;
  cells_.assign(n, Cell());
  serial_ = 0;
  footprint_counts_.assign(footprint_ ? n : 0, 0);
  tilesW_ = width_ / kTile;
  tilesH_ = height_ / kTile;
  gate_.assign(size_t(tilesW_) * tilesH_, kGateClosed);
}

void GridStorage::release() {
  cells_.clear();
  footprint_counts_.clear();
  gate_.clear();
  width_ = height_ = tilesW_ = tilesH_ = 0;
}

void GridStorage::ensureCovers(const CellBox& b) {
  if (b.empty()) return;
  if (cells_.empty()) {
    reset(b);
    return;
  }
  if (b.c0 >= col0_ && b.r0 >= row0_ && b.c1 < col0_ + width_ && b.r1 < row0_ + height_) return;
  // Grow by a quarter of the size on each side that needs it, so that a map growing along a
  // corridor does not copy itself at every node.
  const int mx = std::max(4 * kTile, width_ / 4), my = std::max(4 * kTile, height_ / 4);
  const int nc0 = b.c0 < col0_ ? floorTo(b.c0 - mx, kTile) : col0_;
  const int nr0 = b.r0 < row0_ ? floorTo(b.r0 - my, kTile) : row0_;
  const int nc1 = b.c1 >= col0_ + width_ ? floorTo(b.c1 + mx, kTile) + kTile : col0_ + width_;
  const int nr1 = b.r1 >= row0_ + height_ ? floorTo(b.r1 + my, kTile) + kTile : row0_ + height_;
  const int nw = nc1 - nc0, nh = nr1 - nr0;
  std::vector<Cell> c(size_t(nw) * nh);
  std::vector<uint16_t> f(footprint_ ? size_t(nw) * nh : 0, 0);
  for (int r = 0; r < height_; ++r) {
    const size_t src = size_t(r) * width_, dst = size_t(r + row0_ - nr0) * nw + (col0_ - nc0);
    std::copy_n(cells_.begin() + src, width_, c.begin() + dst);
    if (footprint_) std::copy_n(footprint_counts_.begin() + src, width_, f.begin() + dst);
  }
  cells_.swap(c);
  footprint_counts_.swap(f);
  col0_ = nc0; row0_ = nr0; width_ = nw; height_ = nh;
  tilesW_ = width_ / kTile;
  tilesH_ = height_ / kTile;
  gate_.assign(size_t(tilesW_) * tilesH_, kGateClosed);
}

long GridStorage::apply(const NodeCells& n, const Transform& pose, bool masked, std::vector<int64_t>* tiles,
                        uint32_t key) {
  if (++serial_ == 0) {
    for (Cell& c : cells_) c.stamp = 0;
    serial_ = 1;
  }
  const CellProjector proj(pose, cellSize_);
  const uint16_t s = serial_;
  const unsigned w = static_cast<unsigned>(width_), h = static_cast<unsigned>(height_);
  Cell* const cells = cells_.data();
  const uint32_t* const gate = gate_.data();
  const int tilesW = tilesW_, col0 = col0_, row0 = row0_;
  const int lo = min_, hi = max_;
  long updates = 0;
  int lastTileCol = std::numeric_limits<int>::min(), lastTileRow = 0;
  int cols[kChunk], rows[kChunk];
  if (tiles) tiles->clear();
  // Masked: a run of cells lies on a segment of the world; one whose segment (with a cell of
  // slack for rounding) touches no tile open to this node would write nothing, it is not projected.
  const float inv = 1.0f / cellSize_;
  const Affine a(pose);
  auto touchesDirty = [&](const cv::Point2f& p0, const cv::Point2f& p1) {
    if (!masked) return true;
    const cv::Point3f q0(p0.x, p0.y, 0.f), q1(p1.x, p1.y, 0.f);
    const float x0 = a.x(q0) * inv, x1 = a.x(q1) * inv, y0 = a.y(q0) * inv, y1 = a.y(q1) * inv;
    const int c0 = std::max(0, fastFloor(std::min(x0, x1)) - 1 - col0);
    const int c1 = std::min(int(w) - 1, fastFloor(std::max(x0, x1)) + 1 - col0);
    const int r0 = std::max(0, fastFloor(std::min(y0, y1)) - 1 - row0);
    const int r1 = std::min(int(h) - 1, fastFloor(std::max(y0, y1)) + 1 - row0);
    for (int tr = r0 >> kTileShift; tr <= (r1 >> kTileShift) && r0 <= r1; ++tr) {
      for (int tc = c0 >> kTileShift; tc <= (c1 >> kTileShift) && c0 <= c1; ++tc) {
        if (key >= gate[size_t(tr) * tilesW + tc]) return true;
      }
    }
    return false;
  };
  // Obstacles first, so a cell this node saw occupied is not also freed by it.
  for (const auto& [set, delta] : {std::pair<const CellSet*, int>{&n.obstacles(), hit_}, {&n.free(), miss_}}) {
    set->forEachBatch([&, delta = delta](const float* x, const float* y, const float* z, int m) {
      proj.project(x, y, z, m, cols, rows);
      for (int k = 0; k < m; ++k) {
        const int col = cols[k] - col0, row = rows[k] - row0;
        if (static_cast<unsigned>(col) >= w || static_cast<unsigned>(row) >= h) {
          continue;  // storage covers the node's box: only float rounding at a border lands here
        }
        const int tc = col >> kTileShift, tr = row >> kTileShift;
        if (masked && key < gate[size_t(tr) * tilesW + tc]) continue;
        if (tiles && (tc != lastTileCol || tr != lastTileRow)) {
          lastTileCol = tc;
          lastTileRow = tr;
          tiles->push_back(tileKey(cols[k], rows[k]));
        }
        Cell& cell = cells[size_t(row) * w + col];
        if (cell.stamp == s) continue;  // one update per node and cell
        cell.stamp = s;
        const int v = cell.logOdds;
        cell.logOdds = static_cast<int16_t>(std::min(hi, std::max(lo, v == kUnknownFixed ? delta : v + delta)));
        ++updates;
      }
    }, touchesDirty);
  }
  if (tiles) sortUnique(*tiles);
  return updates;
}

void GridStorage::addFootprint(const Transform& pose, float radius, int sign) {
  if (!footprint_ || footprint_counts_.empty()) return;
  const CellBox b = diskBox(pose, radius);
  const float r2 = radius * radius, x = float(pose.x()), y = float(pose.y());
  for (int r = b.r0; r <= b.r1; ++r) {
    for (int c = b.c0; c <= b.c1; ++c) {
      const float dx = (c + 0.5f) * cellSize_ - x, dy = (r + 0.5f) * cellSize_ - y;
      const int lc = c - col0_, lr = r - row0_;
      if (dx * dx + dy * dy > r2 || lc < 0 || lr < 0 || lc >= width_ || lr >= height_) continue;
      uint16_t& f = footprint_counts_[size_t(lr) * width_ + lc];
      f = static_cast<uint16_t>(f + sign);
    }
  }
}

bool GridStorage::tileInside(int64_t t) const {
  const int tc = tileCol(t) - col0_ / kTile, tr = tileRow(t) - row0_ / kTile;
  return tc >= 0 && tr >= 0 && tc < tilesW_ && tr < tilesH_;
}
size_t GridStorage::tileIndex(int64_t t) const {
  return size_t(tileRow(t) - row0_ / kTile) * tilesW_ + (tileCol(t) - col0_ / kTile);
}
void GridStorage::clearDirty() { std::fill(gate_.begin(), gate_.end(), kGateClosed); }
void GridStorage::markDirty(int64_t t) {
  if (tileInside(t) && gate_[tileIndex(t)] == kGateClosed) gate_[tileIndex(t)] = kGateOpen;
}
void GridStorage::markDirty(const CellBox& b) {
  if (b.empty()) return;
  for (int tr = b.r0 >> kTileShift; tr <= (b.r1 >> kTileShift); ++tr) {
    for (int tc = b.c0 >> kTileShift; tc <= (b.c1 >> kTileShift); ++tc) {
      // UBSan fix (make test-asan): no left shift of a negative row (see tileKey).
      markDirty(static_cast<int64_t>(static_cast<uint64_t>(static_cast<int64_t>(tr)) << 32) ^
                static_cast<int64_t>(static_cast<uint32_t>(tc)));
    }
  }
}
void GridStorage::markAllDirty() { std::fill(gate_.begin(), gate_.end(), kGateOpen); }
bool GridStorage::isDirty(int64_t t) const { return tileInside(t) && gate_[tileIndex(t)] != kGateClosed; }
void GridStorage::setGate(int64_t t, uint32_t g) {
  if (isDirty(t)) gate_[tileIndex(t)] = g;
}
long GridStorage::dirtyTiles() const {
  return static_cast<long>(std::count_if(gate_.begin(), gate_.end(), [](uint32_t g) { return g != kGateClosed; }));
}
std::vector<int64_t> GridStorage::dirtyTileKeys() const {
  std::vector<int64_t> out;
  for (int tr = 0; tr < tilesH_; ++tr) {
    for (int tc = 0; tc < tilesW_; ++tc) {
      if (gate_[size_t(tr) * tilesW_ + tc] != kGateClosed) out.push_back(tileKey(col0_ + tc * kTile, row0_ + tr * kTile));
    }
  }
  return out;
}
void GridStorage::clearDirtyCells() {
  for (int tr = 0; tr < tilesH_; ++tr) {
    for (int tc = 0; tc < tilesW_; ++tc) {
      if (gate_[size_t(tr) * tilesW_ + tc] == kGateClosed) continue;
      for (int r = tr * kTile; r < (tr + 1) * kTile; ++r) {
        for (int c = tc * kTile; c < (tc + 1) * kTile; ++c) cells_[size_t(r) * width_ + c].logOdds = kUnknownFixed;
      }
    }
  }
}
void GridStorage::captureTile(int64_t t, std::vector<int16_t>& out) const {
  out.assign(kTileCells, kUnknownFixed);
  if (!tileInside(t)) return;
  const int c0 = tileCol(t) * kTile - col0_, r0 = tileRow(t) * kTile - row0_;
  for (int r = 0; r < kTile; ++r) {
    const Cell* src = cells_.data() + size_t(r0 + r) * width_ + c0;
    for (int c = 0; c < kTile; ++c) out[size_t(r) * kTile + c] = src[c].logOdds;
  }
}
void GridStorage::restoreTile(int64_t t, const std::vector<int16_t>& in) {
  if (!tileInside(t) || in.size() != size_t(kTileCells)) return;
  const int c0 = tileCol(t) * kTile - col0_, r0 = tileRow(t) * kTile - row0_;
  for (int r = 0; r < kTile; ++r) {
    Cell* dst = cells_.data() + size_t(r0 + r) * width_ + c0;
    for (int c = 0; c < kTile; ++c) dst[c].logOdds = in[size_t(r) * kTile + c];
  }
}

GridMap GridStorage::toMap(float thr, int minCells, bool eroded) const {
  GridMap out;
  if (cells_.empty()) return out;
  // Bounds of what is known (footprint cells count: the robot was there).
  int c0 = width_, r0 = height_, c1 = -1, r1 = -1;
  for (int r = 0; r < height_; ++r) {
    const Cell* l = cells_.data() + size_t(r) * width_;
    const uint16_t* f = footprint_counts_.empty() ? nullptr : footprint_counts_.data() + size_t(r) * width_;
    for (int c = 0; c < width_; ++c) {
      if (l[c].logOdds != kUnknownFixed || (f && f[c] > 0)) {
        c0 = std::min(c0, c); c1 = std::max(c1, c);
        r0 = std::min(r0, r); r1 = std::max(r1, r);
      }
    }
  }
  if (c1 < 0) return out;
  // GridGlobal/MinSize: pad evenly to at least that many cells in each direction.
  if (c1 - c0 + 1 < minCells) {
    const int extra = minCells - (c1 - c0 + 1);
    c0 -= extra / 2;
    c1 += extra - extra / 2;
  }
  if (r1 - r0 + 1 < minCells) {
    const int extra = minCells - (r1 - r0 + 1);
    r0 -= extra / 2;
    r1 += extra - extra / 2;
  }
  out.resolution = cellSize_;
  out.originX = double(col0_ + c0) * cellSize_;
  out.originY = double(row0_ + r0) * cellSize_;
  out.data = cv::Mat(r1 - r0 + 1, c1 - c0 + 1, CV_8SC1, cv::Scalar(GridMap::kUnknown));
  for (int r = std::max(0, r0); r <= std::min(r1, height_ - 1); ++r) {
    int8_t* o = out.data.ptr<int8_t>(r - r0);
    const Cell* l = cells_.data() + size_t(r) * width_;
    const uint16_t* f = footprint_counts_.empty() ? nullptr : footprint_counts_.data() + size_t(r) * width_;
    for (int c = std::max(0, c0); c <= std::min(c1, width_ - 1); ++c) {
      const int lv = l[c].logOdds;
      int8_t v = lv == kUnknownFixed ? GridMap::kUnknown : (float(lv) > thr ? GridMap::kOccupied : GridMap::kFree);
      if (f && f[c] > 0) v = GridMap::kFree;  // where the robot has been cannot be an obstacle
      o[c - c0] = v;
    }
  }
  if (eroded) {
    // An obstacle cell with no obstacle among its 8 neighbours but free space beside it is a
    // speck (a person walking by, a sensor glitch): it becomes free.
    const cv::Mat src = out.data.clone();
    for (int r = 0; r < src.rows; ++r) {
      for (int c = 0; c < src.cols; ++c) {
        if (src.at<int8_t>(r, c) != GridMap::kOccupied) continue;
        bool neighbourObstacle = false, neighbourFree = false;
        for (int dr = -1; dr <= 1; ++dr) {
          for (int dc = -1; dc <= 1; ++dc) {
            const int rr = r + dr, cc = c + dc;
            if ((dr == 0 && dc == 0) || rr < 0 || cc < 0 || rr >= src.rows || cc >= src.cols) continue;
            neighbourObstacle |= src.at<int8_t>(rr, cc) == GridMap::kOccupied;
            neighbourFree |= src.at<int8_t>(rr, cc) == GridMap::kFree;
          }
        }
        if (!neighbourObstacle && neighbourFree) out.data.at<int8_t>(r, c) = GridMap::kFree;
      }
    }
  }
  return out;
}

float GridStorage::logOddsAt(double x, double y) const {
  if (cells_.empty()) return kUnknownLogOdds;
  const CellProjector proj(Transform::Identity(), cellSize_);
  const float px = float(x), py = float(y), pz = 0.0f;
  int c, r;
  proj.project(&px, &py, &pz, 1, &c, &r);
  c -= col0_;
  r -= row0_;
  if (c < 0 || r < 0 || c >= width_ || r >= height_) return kUnknownLogOdds;
  const int16_t v = cells_[size_t(r) * width_ + c].logOdds;
  return v == kUnknownFixed ? kUnknownLogOdds : float(v) / kLogOddsScale;
}

size_t GridStorage::bytes() const {
  return cells_.size() * sizeof(Cell) + footprint_counts_.size() * sizeof(uint16_t) + gate_.size() * sizeof(uint32_t);
}

}  // namespace rtabmap::maps_detail

#include "rtabmap_core/registration/CorrelativeScanMatcher.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {

namespace {

// The deepest level: 2^8 cells per top-level step is already wider than any useful window.
constexpr int kMaxLevels = 8;
// Reference cells within this many cells of a point get its Gaussian spread.
constexpr int kKernelRadius = 2;

// The reference likelihood grid and its max-pooled levels: level h holds, at (x, y), the
// largest level-0 value over the cells [x, x + 2^h) x [y, y + 2^h). A scan scored on level h at
// an offset is therefore an upper bound of its score at every offset of that block: what lets
// branch and bound discard a whole block at once.
class LikelihoodLevels {
 public:
  LikelihoodLevels(const std::vector<Eigen::Vector2f>& reference, const Eigen::Vector2f& min, const Eigen::Vector2f& max,
                   float resolution, int levels)
      : resolution_(resolution), origin_(min) {
    width_ = static_cast<int>(std::ceil((max.x() - min.x()) / resolution)) + 1;
    height_ = static_cast<int>(std::ceil((max.y() - min.y()) / resolution)) + 1;
    grids_.assign(levels + 1, std::vector<float>());
    std::vector<float>& g0 = grids_[0];
    g0.assign(static_cast<size_t>(width_) * height_, 0.0f);
    // From the distance between the cell's centre and the point itself, not between cells: a
    // scan point landing in the cell of a reference point scores near 1 wherever it is in it.
    const float inverseTwoSigma2 = 1.0f / (2.0f * resolution * resolution);
    for (const Eigen::Vector2f& p : reference) {
      const Eigen::Vector2i c = cellOf(p);
      for (int dy = -kKernelRadius; dy <= kKernelRadius; ++dy) {
        for (int dx = -kKernelRadius; dx <= kKernelRadius; ++dx) {
          const int x = c.x() + dx, y = c.y() + dy;
          if (x < 0 || y < 0 || x >= width_ || y >= height_) continue;
          const Eigen::Vector2f centre = origin_ + Eigen::Vector2f(x + 0.5f, y + 0.5f) * resolution;
          float& v = g0[static_cast<size_t>(y) * width_ + x];
          v = std::max(v, std::exp(-(centre - p).squaredNorm() * inverseTwoSigma2));
        }
      }
    }
    for (int h = 1; h <= levels; ++h) {
      const int s = 1 << (h - 1);
      const std::vector<float>& below = grids_[h - 1];
      std::vector<float>& g = grids_[h];
      g.assign(below.size(), 0.0f);
      for (int y = 0; y < height_; ++y) {
        for (int x = 0; x < width_; ++x) {
          float v = below[static_cast<size_t>(y) * width_ + x];
          if (x + s < width_) v = std::max(v, below[static_cast<size_t>(y) * width_ + x + s]);
          if (y + s < height_) {
            v = std::max(v, below[static_cast<size_t>(y + s) * width_ + x]);
            if (x + s < width_) v = std::max(v, below[static_cast<size_t>(y + s) * width_ + x + s]);
          }
          g[static_cast<size_t>(y) * width_ + x] = v;
        }
      }
    }
  }

  Eigen::Vector2i cellOf(const Eigen::Vector2f& p) const {
    return Eigen::Vector2i(static_cast<int>(std::floor((p.x() - origin_.x()) / resolution_)),
                           static_cast<int>(std::floor((p.y() - origin_.y()) / resolution_)));
  }

  // Mean over the cells of the value of level h at cell + offset (0 outside the grid). A block
  // starting left of (or under) the grid but reaching into it is bounded by the level's value
  // at the grid's edge, which covers the block's part inside.
  float score(const std::vector<Eigen::Vector2i>& cells, int h, int ox, int oy) const {
    if (cells.empty()) return 0.0f;
    const std::vector<float>& g = grids_[h];
    const int span = 1 << h;
    double sum = 0.0;
    for (const Eigen::Vector2i& c : cells) {
      int x = c.x() + ox, y = c.y() + oy;
      if (x >= width_ || y >= height_ || x + span <= 0 || y + span <= 0) continue;
      x = std::max(x, 0);
      y = std::max(y, 0);
      sum += g[static_cast<size_t>(y) * width_ + x];
    }
    return static_cast<float>(sum / cells.size());
  }

 private:
  float resolution_;
  Eigen::Vector2f origin_;
  int width_ = 0, height_ = 0;
  std::vector<std::vector<float>> grids_;
};

struct Candidate {
  int rotation = 0;  // index into the rotated scans
  int ox = 0, oy = 0;  // offset in cells from the guess' translation
  float score = 0.0f;
};

struct Search {
  const LikelihoodLevels& levels;
  const std::vector<std::vector<Eigen::Vector2i>>& rotated;  // scan cells per rotation
  int window;                                                // cells
  long scored = 0;
  float best;  // the score to beat (minScore at first)
  Candidate bestCandidate;
  bool found = false;
  // Second-peak search (Olson 2009, section IV.C: a match is only as good as its margin over the
  // next hypothesis): poses within `separation` cells and `rotationSeparation` rotation steps of
  // `exclude` are left out. A block stays an upper bound of its far leaves.
  const Candidate* exclude = nullptr;
  int separation = 0, rotationSeparation = 0;

  bool nearExcluded(int ox, int oy) const {
    const int dx = ox - exclude->ox, dy = oy - exclude->oy;
    return dx * dx + dy * dy <= separation * separation;
  }
  // True when every leaf of the block is near the excluded peak. A pose turned farther than the
  // angular separation is another hypothesis even in the same place (a round hall seen rotated).
  bool blockExcluded(const Candidate& c, int h) const {
    if (!exclude || std::abs(c.rotation - exclude->rotation) > rotationSeparation) return false;
    const int span = (1 << h) - 1;
    return nearExcluded(c.ox, c.oy) && nearExcluded(c.ox + span, c.oy) && nearExcluded(c.ox, c.oy + span) &&
           nearExcluded(c.ox + span, c.oy + span);
  }

  Candidate scoredCandidate(int rotation, int ox, int oy, int h) {
    ++scored;
    return Candidate{rotation, ox, oy, levels.score(rotated[rotation], h, ox, oy)};
  }

  // Depth first, best child first: a good pose is found early and bounds the rest.
  void branch(std::vector<Candidate>& candidates, int h) {
    std::sort(candidates.begin(), candidates.end(),
              [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    for (const Candidate& c : candidates) {
      if (c.score <= best) return;  // sorted: no other candidate here can do better
      if (blockExcluded(c, h)) continue;
      if (h == 0) {
        best = c.score;
        bestCandidate = c;
        found = true;
        return;
      }
      const int s = 1 << (h - 1);
      std::vector<Candidate> children;
      for (int dy = 0; dy <= s; dy += s) {
        for (int dx = 0; dx <= s; dx += s) {
          if (c.ox + dx > window || c.oy + dy > window) continue;
          children.push_back(scoredCandidate(c.rotation, c.ox + dx, c.oy + dy, h - 1));
        }
      }
      branch(children, h - 1);
    }
  }
};

}  // namespace

bool CorrelativeOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (!(resolution > 0.0f) || !std::isfinite(resolution)) return fail("correlative matching: resolution must be > 0");
  if (!(linearWindow >= 0.0f) || !std::isfinite(linearWindow)) return fail("correlative matching: linear window must be >= 0");
  if (!(angularWindow >= 0.0f) || !(angularWindow <= float(M_PI))) {
    return fail("correlative matching: angular window must be in [0, pi]");
  }
  if (!(minScore > 0.0f) || !(minScore <= 1.0f)) return fail("correlative matching: minimum score must be in (0, 1]");
  if (!(maxSecondPeakRatio > 0.0f) || !(maxSecondPeakRatio <= 1.0f)) {
    return fail("correlative matching: second peak ratio must be in (0, 1]");
  }
  if (!(peakSeparation >= 0.0f) || !std::isfinite(peakSeparation) || !(peakAngleSeparation >= 0.0f) ||
      !std::isfinite(peakAngleSeparation)) {
    return fail("correlative matching: peak separations must be >= 0");
  }
  if (linearWindow / resolution > 10000.0f) return fail("correlative matching: window over 10,000 cells");
  return true;
}

CorrelativeResult matchCorrelative(const std::vector<Eigen::Vector2f>& reference,
                                   const std::vector<Eigen::Vector2f>& scan, const Eigen::Vector3f& guess,
                                   const CorrelativeOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw ParameterError(why);
  CorrelativeResult result;
  if (reference.empty() || scan.empty()) {
    result.why = "correlative matching: empty reference or scan";
    return result;
  }
  if (!guess.allFinite()) {
    result.why = "correlative matching: non-finite guess";
    return result;
  }
  // The scan's reach decides the rotation step and the part of the reference it can touch.
  float reach = 0.0f;
  for (const Eigen::Vector2f& q : scan) reach = std::max(reach, q.norm());
  reach = std::max(reach, o.resolution);
  const Eigen::Vector2f t(guess.x(), guess.y());
  const float margin = reach + o.linearWindow + (kKernelRadius + 1) * o.resolution;
  Eigen::Vector2f lo = t.array() - margin, hi = t.array() + margin;
  std::vector<Eigen::Vector2f> near;
  Eigen::Vector2f rmin = hi, rmax = lo;
  for (const Eigen::Vector2f& p : reference) {
    if (!p.allFinite() || (p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    near.push_back(p);
    rmin = rmin.cwiseMin(p);
    rmax = rmax.cwiseMax(p);
  }
  if (near.empty()) {
    result.why = "correlative matching: no reference point within reach of the scan";
    return result;
  }
  // The grid spans what the reference has near the guess, plus the kernel's spread.
  const float pad = (kKernelRadius + 1) * o.resolution;
  rmin.array() -= pad;
  rmax.array() += pad;

  const int window = static_cast<int>(std::ceil(o.linearWindow / o.resolution));
  int levels = 0;
  while (levels < kMaxLevels && (1 << levels) * 4 < 2 * window + 1) ++levels;
  const LikelihoodLevels grid(near, rmin, rmax, o.resolution, levels);

  // Rotation step: the farthest scan point moves by one cell (Hess et al., eq. 7).
  const float step = std::acos(std::max(-1.0f, 1.0f - o.resolution * o.resolution / (2.0f * reach * reach)));
  const int rotations = step > 0.0f ? static_cast<int>(std::ceil(o.angularWindow / step)) : 0;
  std::vector<std::vector<Eigen::Vector2i>> rotated;
  std::vector<float> yaws;
  for (int a = -rotations; a <= rotations; ++a) {
    const float yaw = guess.z() + a * step;
    const float c = std::cos(yaw), s = std::sin(yaw);
    std::vector<Eigen::Vector2i> cells;
    cells.reserve(scan.size());
    for (const Eigen::Vector2f& q : scan) {
      if (!q.allFinite()) continue;
      cells.push_back(grid.cellOf(Eigen::Vector2f(c * q.x() - s * q.y(), s * q.x() + c * q.y()) + t));
    }
    rotated.push_back(std::move(cells));
    yaws.push_back(yaw);
  }
  result.guessScore = grid.score(rotated[rotations], 0, 0, 0);

  Search search{grid, rotated, window, 0, o.minScore - 1e-6f, Candidate(), false};
  std::vector<Candidate> top;
  const int topStep = 1 << levels;
  for (int r = 0; r < static_cast<int>(rotated.size()); ++r) {
    for (int oy = -window; oy <= window; oy += topStep) {
      for (int ox = -window; ox <= window; ox += topStep) top.push_back(search.scoredCandidate(r, ox, oy, levels));
    }
  }
  search.branch(top, levels);
  result.scoredCandidates = search.scored;
  if (!search.found) {
    std::ostringstream m;
    m << "correlative matching: no pose within " << o.linearWindow << " m and " << o.angularWindow
      << " rad of the guess scores " << o.minScore << " (the guess scores " << result.guessScore << ")";
    result.why = m.str();
    return result;
  }
  const Candidate& b = search.bestCandidate;
  result.score = b.score;
  result.pose = Eigen::Vector3f(t.x() + b.ox * o.resolution, t.y() + b.oy * o.resolution, yaws[b.rotation]);
  if (o.maxSecondPeakRatio < 1.0f) {
    // Only whether some far pose reaches the ratio matters: that is the bound to beat.
    const int separation = static_cast<int>(std::ceil(o.peakSeparation / o.resolution));
    const int rotationSeparation = step > 0.0f ? static_cast<int>(std::ceil(o.peakAngleSeparation / step)) : 0;
    Search second{grid, rotated, window, 0, o.maxSecondPeakRatio * b.score - 1e-6f, Candidate(), false,
                  &b,   separation, rotationSeparation};
    // `top` keeps its top-level scores: the first search only sorted it.
    second.branch(top, levels);
    result.scoredCandidates += second.scored;
    if (second.found) {
      result.secondScore = second.best;
      std::ostringstream m;
      m << "correlative matching: ambiguous, a pose over " << o.peakSeparation << " m or " << o.peakAngleSeparation
        << " rad from the best scores "
        << second.best << " against " << b.score << " (ratio over " << o.maxSecondPeakRatio << ")";
      result.why = m.str();
      return result;
    }
  }
  result.found = true;
  return result;
}

}  // namespace rtabmap

#include "rtabmap_core/sim/World.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rtabmap::sim {

namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

double signedArea(const std::vector<Eigen::Vector2d>& p) {
  double area = 0.0;
  for (size_t i = 0; i < p.size(); ++i) area += cross(p[i], p[(i + 1) % p.size()]);
  return 0.5 * area;
}

double pointSegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double u = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + u * ab - p).norm();
}

}  // namespace

World::World(double ceilingHeight) : ceilingHeight_(ceilingHeight) {
  if (!(ceilingHeight > 0.0)) throw std::invalid_argument("World: ceiling height must be > 0");
}

int World::addTexture(const Texture& texture) {
  textures_.push_back(texture);
  return static_cast<int>(textures_.size()) - 1;
}

int World::addSolid(const std::vector<Eigen::Vector2d>& polygon, float height, SolidKind kind,
                    const std::vector<SurfaceMaterial>& sides, const SurfaceMaterial& top,
                    const std::string& label) {
  if (finalized_) throw std::logic_error("World::addSolid after finalize()");
  if (polygon.size() < 3) throw std::invalid_argument("World::addSolid: a polygon needs 3 vertices");
  if (sides.empty() || (sides.size() != 1 && sides.size() != polygon.size())) {
    throw std::invalid_argument("World::addSolid: give one material, or one per edge");
  }
  const double area = signedArea(polygon);
  if (std::fabs(area) < 1e-12) throw std::invalid_argument("World::addSolid: degenerate polygon");
  const bool ccw = area > 0.0;
  Solid solid;
  solid.polygon = polygon;
  if (!ccw) std::reverse(solid.polygon.begin(), solid.polygon.end());
  solid.height = height;
  solid.kind = kind;
  solid.top = top;
  solid.label = label;
  solid.firstFace = static_cast<int>(faces_.size());
  solid.faceCount = static_cast<int>(polygon.size());
  const int solidIndex = static_cast<int>(solids_.size());
  for (size_t i = 0; i < polygon.size(); ++i) {
    // Edge i as given; swapped for a clockwise polygon so that its right side is outside.
    const Eigen::Vector2d& p = polygon[i];
    const Eigen::Vector2d& q = polygon[(i + 1) % polygon.size()];
    Face f;
    f.a = ccw ? p : q;
    f.b = ccw ? q : p;
    f.length = (f.b - f.a).norm();
    f.dir = f.length > 0.0 ? Eigen::Vector2d((f.b - f.a) / f.length) : Eigen::Vector2d(1, 0);
    f.normal = Eigen::Vector2d(f.dir.y(), -f.dir.x());
    f.height = height;
    f.solid = solidIndex;
    f.material = sides.size() == 1 ? sides[0] : sides[i];
    faces_.push_back(f);
  }
  solids_.push_back(std::move(solid));
  return solidIndex;
}

void World::addDecal(int face, const Decal& decal) {
  if (finalized_) throw std::logic_error("World::addDecal after finalize()");
  if (face < 0 || face >= static_cast<int>(faces_.size())) throw std::out_of_range("World::addDecal: bad face");
  pendingDecals_.emplace_back(face, decal);
}

void World::setRegions(const cv::Mat& regions, double originX, double originY, double cell,
                       const std::vector<SurfaceMaterial>& floors, const std::vector<SurfaceMaterial>& ceilings) {
  if (regions.type() != CV_16UC1 || regions.empty()) throw std::invalid_argument("World::setRegions: expected CV_16UC1");
  double maxId = 0.0;
  cv::minMaxLoc(regions, nullptr, &maxId);
  if (floors.size() <= static_cast<size_t>(maxId) || ceilings.size() <= static_cast<size_t>(maxId)) {
    throw std::invalid_argument("World::setRegions: a region id has no floor/ceiling material");
  }
  regions_ = regions.clone();
  regionOriginX_ = originX;
  regionOriginY_ = originY;
  regionInvCell_ = 1.0 / cell;
  floors_ = floors;
  ceilings_ = ceilings;
}

void World::finalize() {
  // Decals grouped per face, sorted along it.
  std::stable_sort(pendingDecals_.begin(), pendingDecals_.end(), [](const auto& x, const auto& y) {
    return x.first != y.first ? x.first < y.first : x.second.s0 < y.second.s0;
  });
  decals_.clear();
  for (Face& f : faces_) f.decalCount = 0;
  for (const auto& [face, decal] : pendingDecals_) {
    Face& f = faces_[static_cast<size_t>(face)];
    if (f.decalCount == 0) f.firstDecal = static_cast<int>(decals_.size());
    decals_.push_back(decal);
    ++f.decalCount;
  }

  // Grid bounds: all faces, with a margin so no face lies on the outer boundary.
  boundsMin_ = Eigen::Vector2d(std::numeric_limits<double>::max(), std::numeric_limits<double>::max());
  boundsMax_ = -boundsMin_;
  for (const Face& f : faces_) {
    boundsMin_ = boundsMin_.cwiseMin(f.a).cwiseMin(f.b);
    boundsMax_ = boundsMax_.cwiseMax(f.a).cwiseMax(f.b);
  }
  if (faces_.empty()) {
    boundsMin_ = Eigen::Vector2d(0, 0);
    boundsMax_ = Eigen::Vector2d(1, 1);
  }
  boundsMin_ -= Eigen::Vector2d(0.5, 0.5);
  boundsMax_ += Eigen::Vector2d(0.5, 0.5);
  gridW_ = std::max(1, static_cast<int>(std::ceil((boundsMax_.x() - boundsMin_.x()) / cellSize_)));
  gridH_ = std::max(1, static_cast<int>(std::ceil((boundsMax_.y() - boundsMin_.y()) / cellSize_)));
  boundsMax_ = boundsMin_ + Eigen::Vector2d(gridW_ * cellSize_, gridH_ * cellSize_);

  // Each face goes into every cell its (slightly grown) bounding box touches: conservative, and
  // exact for the axis-aligned walls that make most of a building.
  std::vector<std::vector<int>> cells(static_cast<size_t>(gridW_ * gridH_));
  const double eps = 1e-6;
  for (size_t i = 0; i < faces_.size(); ++i) {
    const Face& f = faces_[i];
    const int x0 = std::max(0, static_cast<int>(std::floor((std::min(f.a.x(), f.b.x()) - eps - boundsMin_.x()) / cellSize_)));
    const int x1 = std::min(gridW_ - 1, static_cast<int>(std::floor((std::max(f.a.x(), f.b.x()) + eps - boundsMin_.x()) / cellSize_)));
    const int y0 = std::max(0, static_cast<int>(std::floor((std::min(f.a.y(), f.b.y()) - eps - boundsMin_.y()) / cellSize_)));
    const int y1 = std::min(gridH_ - 1, static_cast<int>(std::floor((std::max(f.a.y(), f.b.y()) + eps - boundsMin_.y()) / cellSize_)));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) cells[static_cast<size_t>(y * gridW_ + x)].push_back(static_cast<int>(i));
    }
  }
  cellStart_.assign(cells.size() + 1, 0);
  cellFaces_.clear();
  for (size_t c = 0; c < cells.size(); ++c) {
    cellStart_[c] = static_cast<int>(cellFaces_.size());
    cellFaces_.insert(cellFaces_.end(), cells[c].begin(), cells[c].end());
  }
  cellStart_[cells.size()] = static_cast<int>(cellFaces_.size());
  finalized_ = true;
}

bool World::castRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir, double tMax, float stopHeight,
                    std::vector<RayHit>& hits) const {
  hits.clear();
  if (!finalized_) throw std::logic_error("World::castRay before finalize()");
  // Clip the ray to the grid's box.
  double t0 = 0.0;
  double t1 = tMax;
  for (int k = 0; k < 2; ++k) {
    if (std::fabs(dir[k]) < 1e-15) {
      if (origin[k] < boundsMin_[k] || origin[k] >= boundsMax_[k]) return false;
      continue;
    }
    double ta = (boundsMin_[k] - origin[k]) / dir[k];
    double tb = (boundsMax_[k] - origin[k]) / dir[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 > t1) return false;

  // Amanatides-Woo traversal of the cells along the ray.
  const Eigen::Vector2d start = origin + t0 * dir;
  int ix = std::clamp(static_cast<int>(std::floor((start.x() - boundsMin_.x()) / cellSize_)), 0, gridW_ - 1);
  int iy = std::clamp(static_cast<int>(std::floor((start.y() - boundsMin_.y()) / cellSize_)), 0, gridH_ - 1);
  const double inf = std::numeric_limits<double>::infinity();
  const int stepX = dir.x() > 0 ? 1 : (dir.x() < 0 ? -1 : 0);
  const int stepY = dir.y() > 0 ? 1 : (dir.y() < 0 ? -1 : 0);
  double tNextX = stepX > 0 ? (boundsMin_.x() + (ix + 1) * cellSize_ - origin.x()) / dir.x()
                  : stepX < 0 ? (boundsMin_.x() + ix * cellSize_ - origin.x()) / dir.x() : inf;
  double tNextY = stepY > 0 ? (boundsMin_.y() + (iy + 1) * cellSize_ - origin.y()) / dir.y()
                  : stepY < 0 ? (boundsMin_.y() + iy * cellSize_ - origin.y()) / dir.y() : inf;
  const double tDeltaX = stepX != 0 ? cellSize_ / std::fabs(dir.x()) : inf;
  const double tDeltaY = stepY != 0 ? cellSize_ / std::fabs(dir.y()) : inf;
  double tCell = t0;
  const double eps = 1e-9;

  while (true) {
    const double tCellEnd = std::min({tNextX, tNextY, t1});
    const size_t firstNew = hits.size();
    const int c = iy * gridW_ + ix;
    for (int k = cellStart_[static_cast<size_t>(c)]; k < cellStart_[static_cast<size_t>(c) + 1]; ++k) {
      const int fi = cellFaces_[static_cast<size_t>(k)];
      const Face& f = faces_[static_cast<size_t>(fi)];
      const Eigen::Vector2d e = f.b - f.a;
      const double denom = cross(dir, e);
      if (std::fabs(denom) < 1e-15) continue;  // parallel: grazing a face is no crossing
      const Eigen::Vector2d w = f.a - origin;
      const double t = cross(w, e) / denom;
      if (t <= eps || t > tMax || t < tCell - eps || t > tCellEnd + eps) continue;
      const double u = cross(w, dir) / denom;
      if (u < 0.0 || u > 1.0) continue;
      // A face spanning several cells, hit on a cell boundary, must count once.
      bool seen = false;
      for (const RayHit& h : hits) {
        if (h.face == fi) {
          seen = true;
          break;
        }
      }
      if (seen) continue;
      RayHit hit;
      hit.t = t;
      hit.face = fi;
      hit.entering = dir.dot(f.normal) < 0.0;
      hit.s = u * f.length;
      hits.push_back(hit);
    }
    if (hits.size() > firstNew + 1) {
      std::sort(hits.begin() + static_cast<std::ptrdiff_t>(firstNew), hits.end(),
                [](const RayHit& a, const RayHit& b) { return a.t < b.t; });
    }
    for (size_t k = firstNew; k < hits.size(); ++k) {
      if (hits[k].entering && faces_[static_cast<size_t>(hits[k].face)].height >= stopHeight) {
        hits.resize(k + 1);
        return true;
      }
    }
    if (tCellEnd >= t1) return false;
    if (tNextX < tNextY) {
      ix += stepX;
      tCell = tNextX;
      tNextX += tDeltaX;
      if (ix < 0 || ix >= gridW_) return false;
    } else {
      iy += stepY;
      tCell = tNextY;
      tNextY += tDeltaY;
      if (iy < 0 || iy >= gridH_) return false;
    }
  }
}

double World::clearance(const Eigen::Vector2d& p, float minHeight) const {
  double best = std::numeric_limits<double>::infinity();
  for (const Face& f : faces_) {
    if (f.height < minHeight) continue;
    best = std::min(best, pointSegmentDistance(p, f.a, f.b));
  }
  return best;
}

bool World::insideSolid(const Eigen::Vector2d& p, float minHeight) const {
  for (const Solid& s : solids_) {
    if (s.height < minHeight) continue;
    bool inside = false;
    const auto& poly = s.polygon;
    for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
      if ((poly[i].y() > p.y()) != (poly[j].y() > p.y()) &&
          p.x() < (poly[j].x() - poly[i].x()) * (p.y() - poly[i].y()) / (poly[j].y() - poly[i].y()) + poly[i].x()) {
        inside = !inside;
      }
    }
    if (inside) return true;
  }
  return false;
}

}  // namespace rtabmap::sim

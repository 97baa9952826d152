// Furniture: bookshelves, cabinets, desks, sofas, boxes, plants, bins against the walls of rooms
// and corridors, and tables standing free in large rooms. A keep-out raster protects the
// robot's routes (door approaches, the path to each room's visit point and the turning space
// there, corridor centre lanes and junctions), so the route planner never meets furniture.
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>

#include "BuildingInternal.h"

namespace rtabmap::sim::detail {

namespace {

constexpr double kCell = 0.05;  // keep-out raster resolution, metres

struct Item {
  const char* label;
  double w0, w1;  // width along the wall
  double d0, d1;  // depth out from the wall
  double h0, h1;  // height
  bool round;     // octagonal (plants, bins): w is the diameter
  double weight;
};

// Rooms: what offices, meeting rooms and stores hold. Boxes are lower than the camera (0.5 m),
// so their tops show; everything else is seen from the side.
const Item kRoomItems[] = {
    {"bookshelf", 0.8, 1.6, 0.3, 0.38, 1.8, 2.1, false, 3.0},
    {"cabinet", 0.8, 1.2, 0.42, 0.5, 0.9, 1.3, false, 3.0},
    {"tall_cabinet", 0.8, 1.0, 0.45, 0.55, 1.8, 2.0, false, 1.5},
    {"desk", 1.2, 1.8, 0.65, 0.8, 0.72, 0.76, false, 3.0},
    {"sofa", 1.5, 2.2, 0.8, 0.9, 0.75, 0.85, false, 1.0},
    {"boxes", 0.4, 0.7, 0.35, 0.6, 0.25, 0.45, false, 1.5},
    {"plant", 0.4, 0.6, 0.0, 0.0, 0.9, 1.6, true, 1.5},
    {"bin", 0.28, 0.4, 0.0, 0.0, 0.4, 0.48, true, 1.0},
    {"counter", 1.8, 2.6, 0.6, 0.65, 0.88, 0.92, false, 1.0},
};
// Corridors: shallow things only (they stand within 0.5 m of the wall).
const Item kCorridorItems[] = {
    {"bench", 1.2, 1.6, 0.38, 0.42, 0.44, 0.47, false, 2.0},
    {"plant", 0.4, 0.5, 0.0, 0.0, 1.0, 1.5, true, 2.0},
    {"bin", 0.3, 0.4, 0.0, 0.0, 0.4, 0.48, true, 1.5},
    {"cabinet", 0.8, 1.2, 0.4, 0.45, 0.9, 1.2, false, 1.0},
};

class KeepOut {
 public:
  KeepOut(double width, double depth)
      : mask_(cv::Mat::zeros(static_cast<int>(std::ceil(depth / kCell)) + 2, static_cast<int>(std::ceil(width / kCell)) + 2, CV_8UC1)) {}
  void polygon(const std::vector<Eigen::Vector2d>& poly) {
    std::vector<cv::Point> pts;
    for (const auto& p : poly) pts.emplace_back(static_cast<int>(std::lround(p.x() / kCell)), static_cast<int>(std::lround(p.y() / kCell)));
    cv::fillConvexPoly(mask_, pts, cv::Scalar(255));
  }
  void rect(double x0, double y0, double x1, double y1) {
    polygon({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}});
  }
  void disc(const Eigen::Vector2d& c, double r) {
    cv::circle(mask_, cv::Point(static_cast<int>(std::lround(c.x() / kCell)), static_cast<int>(std::lround(c.y() / kCell))),
               static_cast<int>(std::ceil(r / kCell)), cv::Scalar(255), cv::FILLED);
  }
  void capsule(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double r) {
    cv::line(mask_, cv::Point(static_cast<int>(std::lround(a.x() / kCell)), static_cast<int>(std::lround(a.y() / kCell))),
             cv::Point(static_cast<int>(std::lround(b.x() / kCell)), static_cast<int>(std::lround(b.y() / kCell))),
             cv::Scalar(255), 2 * static_cast<int>(std::ceil(r / kCell)) + 1);
  }
  bool free(const std::vector<Eigen::Vector2d>& poly) const {
    cv::Mat probe = cv::Mat::zeros(mask_.size(), CV_8UC1);
    std::vector<cv::Point> pts;
    for (const auto& p : poly) pts.emplace_back(static_cast<int>(std::lround(p.x() / kCell)), static_cast<int>(std::lround(p.y() / kCell)));
    const cv::Rect box = cv::boundingRect(pts) & cv::Rect(0, 0, mask_.cols, mask_.rows);
    if (box.area() == 0) return false;
    cv::fillConvexPoly(probe, pts, cv::Scalar(255));
    return cv::countNonZero(probe(box) & mask_(box)) == 0;
  }

 private:
  cv::Mat mask_;
};

std::vector<Eigen::Vector2d> octagon(const Eigen::Vector2d& c, double r) {
  std::vector<Eigen::Vector2d> poly;
  for (int k = 0; k < 8; ++k) {
    const double a = (k + 0.5) * M_PI / 4.0;
    poly.emplace_back(c.x() + r * std::cos(a), c.y() + r * std::sin(a));
  }
  return poly;
}

// The rectangle with its back centred at `back` against a wall, facing `front` (unit).
std::vector<Eigen::Vector2d> rectangle(const Eigen::Vector2d& centre, const Eigen::Vector2d& front, double w, double d) {
  const Eigen::Vector2d side(-front.y(), front.x());
  const Eigen::Vector2d f = 0.5 * d * front;
  const Eigen::Vector2d s = 0.5 * w * side;
  return {centre - f - s, centre - f + s, centre + f + s, centre + f - s};
}

std::vector<Eigen::Vector2d> grown(const std::vector<Eigen::Vector2d>& poly, double margin) {
  Eigen::Vector2d c(0, 0);
  for (const auto& p : poly) c += p;
  c /= static_cast<double>(poly.size());
  std::vector<Eigen::Vector2d> out;
  for (const auto& p : poly) {
    const Eigen::Vector2d d = p - c;
    out.push_back(p + margin * d.normalized() * std::sqrt(2.0));
  }
  return out;
}

void addItem(Context& ctx, const Item& item, std::vector<Eigen::Vector2d> poly, const Eigen::Vector2d& front,
             double height, Rng& rng) {
  World& world = *ctx.building.world;
  double area2 = 0.0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const auto& p = poly[i];
    const auto& q = poly[(i + 1) % poly.size()];
    area2 += p.x() * q.y() - p.y() * q.x();
  }
  if (area2 < 0.0) std::reverse(poly.begin(), poly.end());  // counter-clockwise: normals are the right of edges
  const Palette& p = ctx.palette;
  const std::string label = item.label;
  int frontTex = rng.pick(p.woods), sideTex = frontTex, topTex = frontTex;
  if (label == "bookshelf") {
    frontTex = rng.pick(p.bookshelves);
    sideTex = topTex = rng.pick(p.woods);
  } else if (label == "cabinet" || label == "tall_cabinet" || label == "counter") {
    frontTex = rng.pick(p.cabinets);
    sideTex = topTex = rng.pick(p.metals);
    if (label == "counter") topTex = rng.pick(p.woods);
  } else if (label == "sofa" || label == "bench") {
    frontTex = sideTex = topTex = rng.pick(p.fabrics);
    if (label == "bench") topTex = rng.pick(p.woods);
  } else if (label == "plant") {
    frontTex = sideTex = topTex = rng.pick(p.foliage);
  } else if (label == "bin") {
    frontTex = sideTex = topTex = rng.pick(p.metals);
  }
  std::vector<SurfaceMaterial> sides;
  const float offsetS = static_cast<float>(rng.uniform(0.0, 4.0));
  for (size_t e = 0; e < poly.size(); ++e) {
    const Eigen::Vector2d dir = (poly[(e + 1) % poly.size()] - poly[e]).normalized();
    // Polygons here are counter-clockwise: the outward normal is the right of each edge.
    const Eigen::Vector2d normal(dir.y(), -dir.x());
    SurfaceMaterial m;
    m.texture = normal.dot(front) > 0.7 ? frontTex : sideTex;
    m.offsetS = offsetS + static_cast<float>(poly[e].dot(dir));
    m.offsetT = static_cast<float>(height);  // texture rows start at the top edge (shelves, drawers align)
    m.shade = faceShade(normal);
    m.reflectivity = 0.35f + 0.55f * world.textures()[static_cast<size_t>(m.texture)].meanGrey() / 255.0f;
    sides.push_back(m);
  }
  SurfaceMaterial top;
  top.texture = topTex;
  top.offsetS = offsetS;
  top.shade = 0.95f;
  world.addSolid(poly, static_cast<float>(height), SolidKind::kFurniture, sides, top, label);
}

// One attempt at a wall item in the interior rectangle r: returns true if placed.
bool tryWallItem(Context& ctx, KeepOut& keep, const Rect& r, const Item& item, Rng& rng) {
  const int side = rng.uniformInt(0, 3);  // 0 west wall, 1 east, 2 south, 3 north
  const Eigen::Vector2d fronts[4] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  const Eigen::Vector2d front = fronts[side];
  const double w = rng.uniform(item.w0, item.w1);
  const double d = item.round ? w : rng.uniform(item.d0, item.d1);
  const double height = rng.uniform(item.h0, item.h1);
  const double gap = 0.03;
  const bool alongY = side < 2;
  const double lo = (alongY ? r.y0 : r.x0) + 0.5 * w + 0.05;
  const double hi = (alongY ? r.y1 : r.x1) - 0.5 * w - 0.05;
  if (lo > hi) return false;
  const double along = rng.uniform(lo, hi);
  Eigen::Vector2d centre;
  switch (side) {
    case 0: centre = {r.x0 + gap + 0.5 * d, along}; break;
    case 1: centre = {r.x1 - gap - 0.5 * d, along}; break;
    case 2: centre = {along, r.y0 + gap + 0.5 * d}; break;
    default: centre = {along, r.y1 - gap - 0.5 * d}; break;
  }
  std::vector<Eigen::Vector2d> poly = item.round ? octagon(centre, 0.5 * w) : rectangle(centre, front, w, d);
  if (!keep.free(poly)) return false;
  addItem(ctx, item, poly, front, height, rng);
  keep.polygon(grown(poly, 0.12));
  return true;
}

const Item& pickItem(const Item* items, size_t count, Rng& rng) {
  std::vector<double> weights;
  for (size_t i = 0; i < count; ++i) weights.push_back(items[i].weight);
  return items[static_cast<size_t>(rng.weighted(weights))];
}

}  // namespace

void furnish(Context& ctx, Rng& rng) {
  const Building& b = ctx.building;
  const BuildingSpec& spec = ctx.spec;
  if (spec.furnitureDensity <= 0.0) return;
  KeepOut keep(b.width, b.depth);
  const double cw = spec.corridorWidth;
  const double h = 0.5 * spec.wallThickness;

  // What the robot needs: door approaches, room paths and turning discs, corridor lanes and
  // junctions.
  for (const Door& door : b.doors) {
    const Eigen::Vector2d side(-door.inward.y(), door.inward.x());
    const double half = 0.5 * door.width + 0.35;
    const Eigen::Vector2d a = door.front;
    const Eigen::Vector2d c = door.inside + 0.6 * door.inward;
    keep.polygon({a - half * side, a + half * side, c + half * side, c - half * side});
  }
  for (const Area& area : b.areas) {
    if (area.kind != AreaKind::kRoom) continue;
    for (int di : area.doors) keep.capsule(b.doors[static_cast<size_t>(di)].inside, area.visitPoint, 0.7);
    keep.disc(area.visitPoint, 1.0);
  }
  for (size_t i = 0; i < ctx.corrX.size(); ++i) {
    for (size_t j = 0; j < ctx.corrY.size(); ++j) {
      const Eigen::Vector2d jc(ctx.corrX[i] + 0.5 * cw, ctx.corrY[j] + 0.5 * cw);
      keep.rect(jc.x() - 0.5 * cw - 1.2, jc.y() - 0.5 * cw - 1.2, jc.x() + 0.5 * cw + 1.2, jc.y() + 0.5 * cw + 1.2);
    }
  }
  for (const Area& area : b.areas) {
    if (area.kind != AreaKind::kCorridor) continue;
    const Rect& r = area.rect;
    const bool alongX = r.width() > r.height();
    const double lane = 0.5 * cw - 0.5;  // items stand within 0.5 m of a corridor wall
    const Eigen::Vector2d c = r.centre();
    if (alongX) keep.rect(r.x0, c.y() - lane, r.x1, c.y() + lane);
    else keep.rect(c.x() - lane, r.y0, c.x() + lane, r.y1);
  }

  for (const Area& area : b.areas) {
    const Rect inner{area.rect.x0 + h, area.rect.y0 + h, area.rect.x1 - h, area.rect.y1 - h};
    if (area.kind == AreaKind::kRoom) {
      const double surface = inner.width() * inner.height();
      const int target = std::clamp(static_cast<int>(std::lround(spec.furnitureDensity * surface / 5.0)), 1, 10);
      int placed = 0;
      for (int attempt = 0; attempt < 40 * target && placed < target; ++attempt) {
        const Item& item = pickItem(kRoomItems, std::size(kRoomItems), rng);
        if (tryWallItem(ctx, keep, inner, item, rng)) ++placed;
      }
      // A table in the middle of a large room, turned a little.
      if (surface > 16.0 && rng.chance(0.6 * std::min(1.0, spec.furnitureDensity))) {
        for (int attempt = 0; attempt < 20; ++attempt) {
          const double w = rng.uniform(1.2, 2.0);
          const double d = rng.uniform(0.7, 1.0);
          const double angle = rng.uniform(-0.3, 0.3);
          const double cx = rng.uniform(inner.x0 + 1.2, inner.x1 - 1.2);  // one draw per statement: a fixed order
          const Eigen::Vector2d centre(cx, rng.uniform(inner.y0 + 1.2, inner.y1 - 1.2));
          const Eigen::Vector2d front(std::cos(angle), std::sin(angle));
          const auto poly = rectangle(centre, front, w, d);
          if (!keep.free(poly)) continue;
          static const Item kTable = {"table", 1.2, 2.0, 0.7, 1.0, 0.72, 0.76, false, 1.0};
          addItem(ctx, kTable, poly, front, rng.uniform(0.72, 0.76), rng);
          keep.polygon(grown(poly, 0.12));
          break;
        }
      }
    } else {
      const double length = std::max(area.rect.width(), area.rect.height());
      const int target = static_cast<int>(std::lround(spec.furnitureDensity * length / 9.0));
      int placed = 0;
      for (int attempt = 0; attempt < 30 * target && placed < target; ++attempt) {
        const Item& item = pickItem(kCorridorItems, std::size(kCorridorItems), rng);
        if (tryWallItem(ctx, keep, inner, item, rng)) ++placed;
      }
    }
  }
}

}  // namespace rtabmap::sim::detail

// Wall lines -> wall solids. A line is cut at doorways (openings) and where perpendicular walls
// meet it, so each piece faces a single area on each side and takes that area's material.
#include <algorithm>
#include <cmath>

#include "BuildingInternal.h"

namespace rtabmap::sim::detail {

namespace {

bool insideOpening(const WallLine& line, double a, double b) {
  const double mid = 0.5 * (a + b);
  for (const auto& [o0, o1] : line.openings) {
    if (mid > o0 && mid < o1) return true;
  }
  return false;
}

bool atOpeningEdge(const WallLine& line, double coordinate) {
  for (const auto& [o0, o1] : line.openings) {
    if (std::fabs(coordinate - o0) < 1e-9 || std::fabs(coordinate - o1) < 1e-9) return true;
  }
  return false;
}

}  // namespace

void buildWalls(Context& ctx) {
  World& world = *ctx.building.world;
  const double h = 0.5 * ctx.spec.wallThickness;
  const float height = static_cast<float>(ctx.spec.ceilingHeight);
  const int doorFrame = ctx.palette.woods.front();
  for (const WallLine& line : ctx.lines) {
    std::vector<double> breaks = {line.from, line.to};
    for (double s : line.splits) breaks.push_back(s);
    for (const auto& [o0, o1] : line.openings) {
      breaks.push_back(o0);
      breaks.push_back(o1);
    }
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end(), [](double a, double b) { return std::fabs(a - b) < 1e-9; }),
                 breaks.end());
    for (size_t k = 0; k + 1 < breaks.size(); ++k) {
      const double a = breaks[k];
      const double b = breaks[k + 1];
      if (b - a < 1e-6 || insideOpening(line, a, b)) continue;
      // The ends of a line run half a thickness further, so corners close.
      const double p0 = a - (std::fabs(a - line.from) < 1e-9 ? h : 0.0);
      const double p1 = b + (std::fabs(b - line.to) < 1e-9 ? h : 0.0);
      const double c = line.c;
      std::vector<Eigen::Vector2d> poly;
      if (line.vertical) poly = {{c - h, p0}, {c + h, p0}, {c + h, p1}, {c - h, p1}};
      else poly = {{p0, c - h}, {p1, c - h}, {p1, c + h}, {p0, c + h}};
      std::vector<SurfaceMaterial> sides(4);
      std::vector<int> sideArea(4, -1);
      std::vector<bool> longSide(4, false);
      for (int e = 0; e < 4; ++e) {
        const Eigen::Vector2d& va = poly[static_cast<size_t>(e)];
        const Eigen::Vector2d& vb = poly[static_cast<size_t>((e + 1) % 4)];
        const Eigen::Vector2d dir = (vb - va).normalized();
        const Eigen::Vector2d normal(dir.y(), -dir.x());
        const Eigen::Vector2d mid = 0.5 * (va + vb);
        const bool isLong = line.vertical ? (e == 1 || e == 3) : (e == 0 || e == 2);
        longSide[static_cast<size_t>(e)] = isLong;
        SurfaceMaterial m;
        m.shade = faceShade(normal);
        // Tile variants: one key per wall line and side, so the pieces of a line continue.
        m.variantKey = hash2D(static_cast<int32_t>(std::lround(line.c * 1000.0)),
                              directionIndex(normal) + (line.vertical ? 4 : 0), 0x3c6ef372u);
        if (isLong) {
          const int area = ctx.areaAt(mid.x() + normal.x() * (h + 0.05), mid.y() + normal.y() * (h + 0.05));
          sideArea[static_cast<size_t>(e)] = area;
          if (area >= 0) {
            const Theme& t = ctx.themes[static_cast<size_t>(area)];
            const int d = directionIndex(normal);
            m.texture = t.plainSide[d] ? t.paint : t.accent;
            // Along a straight wall the texture continues from piece to piece.
            m.offsetS = static_cast<float>(va.dot(dir)) + t.shiftS[d];
            m.offsetT = t.shiftT[d];
          } else {
            m.texture = ctx.palette.facade;  // outside, or inside a closed corner shaft
            m.offsetS = static_cast<float>(va.dot(dir));
          }
        } else {
          const double along = line.vertical ? mid.y() : mid.x();
          const double end = (along < 0.5 * (p0 + p1)) ? a : b;
          m.texture = atOpeningEdge(line, end) ? doorFrame : ctx.palette.paints.front();
          m.offsetS = static_cast<float>(va.dot(dir));
        }
        const Texture& tex = world.textures()[static_cast<size_t>(m.texture)];
        m.reflectivity = 0.35f + 0.55f * tex.meanGrey() / 255.0f;
        sides[static_cast<size_t>(e)] = m;
      }
      SurfaceMaterial top;
      top.texture = ctx.palette.plasters.front();
      const int solid = world.addSolid(poly, height, SolidKind::kWall, sides, top, line.facade ? "facade" : "wall");
      for (int e = 0; e < 4; ++e) {
        if (!longSide[static_cast<size_t>(e)] || sideArea[static_cast<size_t>(e)] < 0) continue;
        WallFace wf;
        wf.face = world.solids()[static_cast<size_t>(solid)].firstFace + e;
        wf.area = sideArea[static_cast<size_t>(e)];
        const Face& f = world.faces()[static_cast<size_t>(wf.face)];
        wf.direction = directionIndex(f.normal);
        wf.plain = ctx.themes[static_cast<size_t>(wf.area)].plainSide[wf.direction];
        wf.facade = line.facade;
        ctx.wallFaces.push_back(wf);
      }
    }
  }
}

}  // namespace rtabmap::sim::detail

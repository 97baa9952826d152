// Building layout: corridor grid, blocks, rooms, doors and wall lines; then the other stages
// (palette and themes, walls, furniture, decals, navigation graph) in BuildingInternal.h.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "BuildingInternal.h"

namespace rtabmap::sim {

namespace detail {

int Context::areaAt(double x, double y) const {
  const int i = static_cast<int>(std::floor(x / rasterCell));
  const int j = static_cast<int>(std::floor(y / rasterCell));
  if (i < 0 || j < 0 || i >= areaRaster.cols || j >= areaRaster.rows) return -1;
  return static_cast<int>(areaRaster.at<uint16_t>(j, i)) - 1;
}

int directionIndex(const Eigen::Vector2d& n) {
  if (std::fabs(n.x()) >= std::fabs(n.y())) return n.x() >= 0 ? 0 : 2;
  return n.y() >= 0 ? 1 : 3;
}

}  // namespace detail

namespace {

using detail::Context;
using detail::WallLine;

// Cut positions inside (a, b) giving pieces of about [minW, maxW] (fewer, larger rooms are
// more likely, as in offices).
std::vector<double> splitSpan(double a, double b, double minW, double maxW, Rng& rng) {
  const double length = b - a;
  const int nMin = std::max(1, static_cast<int>(std::ceil(length / maxW)));
  const int nMax = std::max(nMin, static_cast<int>(std::floor(length / minW)));
  const int n = std::min(nMax, nMin + (rng.chance(0.35) ? 1 : 0));
  std::vector<double> weights;
  double total = 0.0;
  for (int i = 0; i < n; ++i) {
    weights.push_back(rng.uniform(1.0, 1.6));
    total += weights.back();
  }
  std::vector<double> cuts;
  double x = a;
  for (int i = 0; i + 1 < n; ++i) {
    x += length * weights[static_cast<size_t>(i)] / total;
    cuts.push_back(x);
  }
  return cuts;
}

int addLine(Context& ctx, bool vertical, double c, double from, double to, bool facade = false) {
  WallLine line;
  line.vertical = vertical;
  line.c = c;
  line.from = from;
  line.to = to;
  line.facade = facade;
  ctx.lines.push_back(line);
  return static_cast<int>(ctx.lines.size()) - 1;
}

int addArea(Context& ctx, AreaKind kind, const Rect& rect, const std::string& name) {
  Area area;
  area.id = static_cast<int>(ctx.building.areas.size());
  area.kind = kind;
  area.rect = rect;
  area.name = name;
  area.visitPoint = rect.centre();
  ctx.building.areas.push_back(area);
  return area.id;
}

// A doorway from `room` onto `corridor` through wall line `lineIndex`, somewhere in [lo, hi]
// along the line (the part of the room's wall that faces the corridor). `inward` points from
// the corridor into the room; `corridorCentre` is the corridor's centre-line coordinate.
void addDoor(Context& ctx, int room, int lineIndex, double lo, double hi, int corridor,
             const Eigen::Vector2d& inward, double corridorCentre, Rng& rng) {
  const BuildingSpec& spec = ctx.spec;
  WallLine& line = ctx.lines[static_cast<size_t>(lineIndex)];
  const double width = rng.uniform(spec.doorMinWidth, spec.doorMaxWidth);
  const double margin = 0.35 + 0.5 * spec.wallThickness;
  const double a = lo + margin + 0.5 * width;
  const double b = hi - margin - 0.5 * width;
  if (a > b) return;  // a room too narrow for a door stays closed (a store room)
  const double along = rng.uniform(a, b);
  line.openings.emplace_back(along - 0.5 * width, along + 0.5 * width);
  Door door;
  door.width = width;
  door.room = room;
  door.corridor = corridor;
  door.inward = inward;
  door.centre = line.vertical ? Eigen::Vector2d(line.c, along) : Eigen::Vector2d(along, line.c);
  door.front = line.vertical ? Eigen::Vector2d(corridorCentre, along) : Eigen::Vector2d(along, corridorCentre);
  door.inside = door.centre + 0.9 * inward;
  const int id = static_cast<int>(ctx.building.doors.size());
  ctx.building.doors.push_back(door);
  ctx.building.areas[static_cast<size_t>(room)].doors.push_back(id);
  ctx.building.areas[static_cast<size_t>(corridor)].doors.push_back(id);
}

void layOutBlock(Context& ctx, int bi, int bj, const Rect& r, int& roomNumber, Rng& rng) {
  const BuildingSpec& spec = ctx.spec;
  // Perimeter walls: south, north, west, east.
  const int south = addLine(ctx, false, r.y0, r.x0, r.x1);
  const int north = addLine(ctx, false, r.y1, r.x0, r.x1);
  const int west = addLine(ctx, true, r.x0, r.y0, r.y1);
  const int east = addLine(ctx, true, r.x1, r.y0, r.y1);
  const int corrSouth = ctx.corridorH[static_cast<size_t>(bj)];
  const int corrNorth = ctx.corridorH[static_cast<size_t>(bj + 1)];
  const int corrWest = ctx.corridorV[static_cast<size_t>(bi)];
  const int corrEast = ctx.corridorV[static_cast<size_t>(bi + 1)];
  const double half = 0.5 * spec.corridorWidth;
  const bool alongX = r.width() >= r.height();  // rooms are laid out along the long side
  const double shortSide = alongX ? r.height() : r.width();
  const bool twoRows = shortSide >= 2.0 * spec.roomMinWidth;
  double middle = alongX ? r.centre().y() : r.centre().x();
  if (twoRows) {
    middle += rng.uniform(-0.15, 0.15) * shortSide;
    if (alongX) addLine(ctx, false, middle, r.x0, r.x1);
    else addLine(ctx, true, middle, r.y0, r.y1);
  }
  // Row 0 faces south (or west), row 1 north (or east); a single row picks one side.
  const int rows = twoRows ? 2 : 1;
  const int singleSide = rng.chance(0.5) ? 0 : 1;
  for (int row = 0; row < rows; ++row) {
    const int side = twoRows ? row : singleSide;
    double lo, hi;  // the row's extent across the long axis
    if (twoRows) {
      lo = row == 0 ? (alongX ? r.y0 : r.x0) : middle;
      hi = row == 0 ? middle : (alongX ? r.y1 : r.x1);
    } else {
      lo = alongX ? r.y0 : r.x0;
      hi = alongX ? r.y1 : r.x1;
    }
    const double a = alongX ? r.x0 : r.y0;
    const double b = alongX ? r.x1 : r.y1;
    std::vector<double> cuts = splitSpan(a, b, spec.roomMinWidth, spec.roomMaxWidth, rng);
    for (double cut : cuts) {
      if (alongX) addLine(ctx, true, cut, lo, hi);
      else addLine(ctx, false, cut, lo, hi);
    }
    cuts.insert(cuts.begin(), a);
    cuts.push_back(b);
    for (size_t k = 0; k + 1 < cuts.size(); ++k) {
      const Rect room = alongX ? Rect{cuts[k], lo, cuts[k + 1], hi} : Rect{lo, cuts[k], hi, cuts[k + 1]};
      const int id = addArea(ctx, AreaKind::kRoom, room, "room " + std::to_string(roomNumber++));
      if (alongX) {
        if (side == 0) addDoor(ctx, id, south, room.x0, room.x1, corrSouth, {0, 1}, r.y0 - half, rng);
        else addDoor(ctx, id, north, room.x0, room.x1, corrNorth, {0, -1}, r.y1 + half, rng);
      } else {
        if (side == 0) addDoor(ctx, id, west, room.y0, room.y1, corrWest, {1, 0}, r.x0 - half, rng);
        else addDoor(ctx, id, east, room.y0, room.y1, corrEast, {-1, 0}, r.x1 + half, rng);
      }
    }
  }
}

// The band of rooms along one facade: rooms between `a` and `b` along the band, between the
// facade and the band's inner wall line `inner`.
void layOutBand(Context& ctx, bool vertical, double facadeC, double innerC, double a, double b, int innerLine,
                int corridor, const Eigen::Vector2d& inward, double corridorCentre, int& roomNumber, Rng& rng) {
  const BuildingSpec& spec = ctx.spec;
  std::vector<double> cuts = splitSpan(a, b, spec.roomMinWidth, spec.roomMaxWidth, rng);
  const double lo = std::min(facadeC, innerC);
  const double hi = std::max(facadeC, innerC);
  for (double cut : cuts) addLine(ctx, !vertical, cut, lo, hi);
  cuts.insert(cuts.begin(), a);
  cuts.push_back(b);
  for (size_t k = 0; k + 1 < cuts.size(); ++k) {
    const Rect room = vertical ? Rect{lo, cuts[k], hi, cuts[k + 1]} : Rect{cuts[k], lo, cuts[k + 1], hi};
    const int id = addArea(ctx, AreaKind::kRoom, room, "room " + std::to_string(roomNumber++));
    addDoor(ctx, id, innerLine, cuts[k], cuts[k + 1], corridor, inward, corridorCentre, rng);
  }
}

void validate(const BuildingSpec& s) {
  auto fail = [](const std::string& why) { throw std::invalid_argument("BuildingSpec: " + why); };
  if (s.blocksX < 1 || s.blocksY < 1) fail("at least one block in each direction");
  if (!(s.corridorWidth >= 1.4)) fail("corridorWidth must be >= 1.4 m (the robot turns in it)");
  if (!(s.roomMinWidth >= s.doorMaxWidth + 1.0)) fail("roomMinWidth must leave room for a door (doorMaxWidth + 1 m)");
  if (!(s.roomMaxWidth >= s.roomMinWidth)) fail("roomMaxWidth < roomMinWidth");
  if (!(s.blockMinWidth >= s.roomMinWidth && s.blockMinDepth >= s.roomMinWidth)) fail("blocks smaller than a room");
  if (!(s.blockMaxWidth >= s.blockMinWidth && s.blockMaxDepth >= s.blockMinDepth)) fail("block max < min");
  if (s.outerRoomDepth != 0.0 && s.outerRoomDepth < s.roomMinWidth) fail("outerRoomDepth must be 0 or >= roomMinWidth");
  if (!(s.ceilingHeight > 1.5)) fail("ceilingHeight must be > 1.5 m");
  if (!(s.wallThickness > 0.02 && s.wallThickness < 0.5)) fail("wallThickness out of (0.02, 0.5) m");
  if (!(s.doorMinWidth >= 0.8 && s.doorMaxWidth >= s.doorMinWidth)) fail("door widths");
  if (s.materialSize < 16 || (s.materialSize & (s.materialSize - 1))) fail("materialSize must be a power of two >= 16");
  if (!(s.materialTexelsPerMetre > 0 && s.decalTexelsPerMetre > 0)) fail("texel densities must be > 0");
  if (s.materialVariants < 1 || s.materialVariants > 64) fail("materialVariants must be in [1, 64]");
}

}  // namespace

int Building::roomCount() const {
  return static_cast<int>(std::count_if(areas.begin(), areas.end(), [](const Area& a) { return a.kind == AreaKind::kRoom; }));
}

Building generateBuilding(const BuildingSpec& spec, uint64_t seed) {
  validate(spec);
  Building building;
  building.spec = spec;
  building.seed = seed;
  building.world = std::make_unique<World>(spec.ceilingHeight);
  Context ctx{building, spec, seed, {}, {}, {}, {}, {}, 0.1, {}, {}, {}, {}};
  Rng rng(seed, "building/layout");

  // Corridor and block coordinates along x and y.
  const double band = spec.outerRoomDepth;
  const double cw = spec.corridorWidth;
  std::vector<double> colW, rowD;
  for (int i = 0; i < spec.blocksX; ++i) colW.push_back(rng.uniform(spec.blockMinWidth, spec.blockMaxWidth));
  for (int j = 0; j < spec.blocksY; ++j) rowD.push_back(rng.uniform(spec.blockMinDepth, spec.blockMaxDepth));
  double x = band;
  for (int i = 0; i <= spec.blocksX; ++i) {
    ctx.corrX.push_back(x);
    x += cw + (i < spec.blocksX ? colW[static_cast<size_t>(i)] : 0.0);
  }
  building.width = x + band;
  double y = band;
  for (int j = 0; j <= spec.blocksY; ++j) {
    ctx.corrY.push_back(y);
    y += cw + (j < spec.blocksY ? rowD[static_cast<size_t>(j)] : 0.0);
  }
  building.depth = y + band;
  const double W = building.width;
  const double H = building.depth;
  building.junctionsX = spec.blocksX + 1;
  building.junctionsY = spec.blocksY + 1;

  // Corridors: the full-length strips between and around the blocks.
  const double gx0 = ctx.corrX.front();
  const double gx1 = ctx.corrX.back() + cw;
  const double gy0 = ctx.corrY.front();
  const double gy1 = ctx.corrY.back() + cw;
  for (int j = 0; j <= spec.blocksY; ++j) {
    ctx.corridorH.push_back(addArea(ctx, AreaKind::kCorridor, Rect{gx0, ctx.corrY[static_cast<size_t>(j)], gx1, ctx.corrY[static_cast<size_t>(j)] + cw},
                                    "corridor H" + std::to_string(j)));
  }
  for (int i = 0; i <= spec.blocksX; ++i) {
    ctx.corridorV.push_back(addArea(ctx, AreaKind::kCorridor, Rect{ctx.corrX[static_cast<size_t>(i)], gy0, ctx.corrX[static_cast<size_t>(i)] + cw, gy1},
                                    "corridor V" + std::to_string(i)));
  }

  // Facade and band walls. Corner squares of the band stay closed (stairs, shafts).
  addLine(ctx, false, 0.0, 0.0, W, true);
  addLine(ctx, false, H, 0.0, W, true);
  addLine(ctx, true, 0.0, 0.0, H, true);
  addLine(ctx, true, W, 0.0, H, true);
  int roomNumber = 101;
  if (band > 0.0) {
    const int southInner = addLine(ctx, false, band, 0.0, W);
    const int northInner = addLine(ctx, false, H - band, 0.0, W);
    const int westInner = addLine(ctx, true, band, 0.0, H);
    const int eastInner = addLine(ctx, true, W - band, 0.0, H);
    layOutBand(ctx, false, 0.0, band, gx0, gx1, southInner, ctx.corridorH.front(), {0, -1}, gy0 + 0.5 * cw, roomNumber, rng);
    layOutBand(ctx, false, H, H - band, gx0, gx1, northInner, ctx.corridorH.back(), {0, 1}, gy1 - 0.5 * cw, roomNumber, rng);
    layOutBand(ctx, true, 0.0, band, gy0, gy1, westInner, ctx.corridorV.front(), {-1, 0}, gx0 + 0.5 * cw, roomNumber, rng);
    layOutBand(ctx, true, W, W - band, gy0, gy1, eastInner, ctx.corridorV.back(), {1, 0}, gx1 - 0.5 * cw, roomNumber, rng);
  }
  for (int j = 0; j < spec.blocksY; ++j) {
    for (int i = 0; i < spec.blocksX; ++i) {
      const double bx0 = ctx.corrX[static_cast<size_t>(i)] + cw;
      const double by0 = ctx.corrY[static_cast<size_t>(j)] + cw;
      const Rect r{bx0, by0, bx0 + colW[static_cast<size_t>(i)], by0 + rowD[static_cast<size_t>(j)]};
      building.blocks.push_back(r);
      layOutBlock(ctx, i, j, r, roomNumber, rng);
    }
  }

  // Where perpendicular walls meet a line, its material may change: split it there.
  for (WallLine& line : ctx.lines) {
    for (const WallLine& other : ctx.lines) {
      if (other.vertical == line.vertical) continue;
      if (other.c > line.from + 1e-6 && other.c < line.to - 1e-6 && line.c >= other.from - 1e-6 && line.c <= other.to + 1e-6) {
        line.splits.push_back(other.c);
      }
    }
  }

  // Area raster: rooms, then corridors (which overlap at junctions).
  ctx.areaRaster = cv::Mat::zeros(static_cast<int>(std::ceil(H / ctx.rasterCell)) + 1,
                                  static_cast<int>(std::ceil(W / ctx.rasterCell)) + 1, CV_16UC1);
  for (const Area& area : building.areas) {
    const int i0 = std::max(0, static_cast<int>(std::floor(area.rect.x0 / ctx.rasterCell)));
    const int i1 = std::min(ctx.areaRaster.cols, static_cast<int>(std::ceil(area.rect.x1 / ctx.rasterCell)));
    const int j0 = std::max(0, static_cast<int>(std::floor(area.rect.y0 / ctx.rasterCell)));
    const int j1 = std::min(ctx.areaRaster.rows, static_cast<int>(std::ceil(area.rect.y1 / ctx.rasterCell)));
    ctx.areaRaster(cv::Range(j0, j1), cv::Range(i0, i1)).setTo(area.id + 1);
  }
  for (const Area& area : building.areas) {
    if (area.kind != AreaKind::kCorridor) continue;
    const int i0 = static_cast<int>(std::floor(area.rect.x0 / ctx.rasterCell));
    const int i1 = static_cast<int>(std::ceil(area.rect.x1 / ctx.rasterCell));
    const int j0 = static_cast<int>(std::floor(area.rect.y0 / ctx.rasterCell));
    const int j1 = static_cast<int>(std::ceil(area.rect.y1 / ctx.rasterCell));
    ctx.areaRaster(cv::Range(j0, j1), cv::Range(i0, i1)).setTo(area.id + 1);
  }

  Rng paletteRng(seed, "building/palette");
  ctx.palette = detail::makePalette(*building.world, spec, building.roomCount(), paletteRng);
  Rng themeRng(seed, "building/themes");
  detail::assignThemes(ctx, themeRng);
  detail::buildWalls(ctx);
  Rng furnitureRng(seed, "building/furniture");
  detail::furnish(ctx, furnitureRng);
  Rng decalRng(seed, "building/decals");
  detail::placeDecals(ctx, decalRng);

  // Floor and ceiling materials per area (region id = area id + 1; 0 = outside).
  std::vector<SurfaceMaterial> floors(building.areas.size() + 1), ceilings(building.areas.size() + 1);
  for (const Area& area : building.areas) {
    const detail::Theme& theme = ctx.themes[static_cast<size_t>(area.id)];
    SurfaceMaterial f;
    f.texture = theme.floor;
    f.shade = 0.85f;
    SurfaceMaterial c;
    c.texture = theme.ceiling;
    floors[static_cast<size_t>(area.id) + 1] = f;
    ceilings[static_cast<size_t>(area.id) + 1] = c;
  }
  building.world->setRegions(ctx.areaRaster, 0.0, 0.0, ctx.rasterCell, floors, ceilings);
  building.world->finalize();
  detail::buildNavGraph(ctx);
  return building;
}

}  // namespace rtabmap::sim

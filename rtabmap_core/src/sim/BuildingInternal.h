#pragma once
// Shared state of the building generator's stages (private to src/sim): layout, palette and
// themes, walls, furniture and decals, navigation graph.
#include <opencv2/core/mat.hpp>

#include <utility>
#include <vector>

#include "rtabmap_core/sim/Building.h"
#include "rtabmap_core/sim/Random.h"

namespace rtabmap::sim::detail {

// A straight wall along a line of the floor plan, before it becomes solids: x = c (vertical,
// running along y from `from` to `to`) or y = c (horizontal, along x).
struct WallLine {
  bool vertical = false;
  double c = 0.0;
  double from = 0.0;
  double to = 0.0;
  bool facade = false;  // an outer wall of the building
  std::vector<std::pair<double, double>> openings;  // doorways [a, b] along the line
  std::vector<double> splits;  // where perpendicular walls meet it (material may change there)
};

// Materials of the building, as texture indices in its World.
struct Palette {
  std::vector<int> paints, plasters, accents, corridorAccents;
  std::vector<int> roomFloors, corridorFloors, ceilings;
  std::vector<int> bookshelves, cabinets, woods, fabrics, foliage, metals;
  int facade = -1;
};

// How an area looks: its materials, and per wall direction (0 +x, 1 +y, 2 -x, 3 -y: the
// direction the wall's visible face points to) whether it is plain and where its texture starts.
struct Theme {
  int paint = -1;
  int accent = -1;
  int floor = -1;
  int ceiling = -1;
  bool plainSide[4] = {true, true, true, true};
  float shiftS[4] = {0, 0, 0, 0};
  float shiftT[4] = {0, 0, 0, 0};
};

// A long wall face that shows inside an area: where decals may go.
struct WallFace {
  int face = -1;
  int area = -1;
  int direction = 0;
  bool plain = true;
  bool facade = false;
};

struct Context {
  Building& building;
  const BuildingSpec& spec;
  uint64_t seed;
  std::vector<WallLine> lines;
  Palette palette;
  std::vector<Theme> themes;       // per area
  std::vector<WallFace> wallFaces;
  cv::Mat areaRaster;              // CV_16UC1: area id + 1, 0 outside
  double rasterCell = 0.1;
  std::vector<int> corridorH, corridorV;  // area id of horizontal corridor j / vertical corridor i
  std::vector<double> corrX, corrY;       // lower edge of vertical corridor i / horizontal corridor j

  // Area id at a floor point, -1 outside.
  int areaAt(double x, double y) const;
};

// Direction index of an axis-aligned unit normal (0 +x, 1 +y, 2 -x, 3 -y).
int directionIndex(const Eigen::Vector2d& normal);

Palette makePalette(World& world, const BuildingSpec& spec, int roomCount, Rng& rng);
void assignThemes(Context& ctx, Rng& rng);
// Light on a vertical face from its orientation: walls facing the main light are brighter.
float faceShade(const Eigen::Vector2d& normal);
void buildWalls(Context& ctx);
void furnish(Context& ctx, Rng& rng);
void placeDecals(Context& ctx, Rng& rng);
void buildNavGraph(Context& ctx);

}  // namespace rtabmap::sim::detail

// The building's materials (a palette generated once per building, reused from room to room)
// and each area's theme: which paint and accent material its walls get, its floor and ceiling.
#include <cmath>

#include "BuildingInternal.h"
#include "rtabmap_core/sim/Materials.h"

namespace rtabmap::sim::detail {

namespace {

std::vector<int> addMaterials(World& world, const BuildingSpec& spec, MaterialKind kind, int count, Rng& rng) {
  std::vector<int> ids;
  for (int i = 0; i < count; ++i) {
    const MaterialSpec m = randomMaterialSpec(kind, rng);
    const int variants = variesPerTile(kind) ? spec.materialVariants : 1;
    ids.push_back(world.addTexture(makeMaterialTexture(m, spec.materialSize, spec.materialTexelsPerMetre, variants)));
  }
  return ids;
}

void append(std::vector<int>& to, const std::vector<int>& from) { to.insert(to.end(), from.begin(), from.end()); }

}  // namespace

Palette makePalette(World& world, const BuildingSpec& spec, int roomCount, Rng& rng) {
  Palette p;
  // Larger buildings get more variety, but still far fewer materials than rooms: repetition
  // across rooms is part of what a place-recognition system must cope with.
  const int extra = std::min(4, roomCount / 25);
  p.paints = addMaterials(world, spec, MaterialKind::kPaint, 5 + extra, rng);
  p.plasters = addMaterials(world, spec, MaterialKind::kPlaster, 2, rng);
  append(p.accents, addMaterials(world, spec, MaterialKind::kBrick, 2, rng));
  append(p.accents, addMaterials(world, spec, MaterialKind::kBlocks, 1, rng));
  append(p.accents, addMaterials(world, spec, MaterialKind::kWoodPanels, 2, rng));
  append(p.accents, addMaterials(world, spec, MaterialKind::kWallpaper, 3 + extra / 2, rng));
  append(p.accents, addMaterials(world, spec, MaterialKind::kWallTiles, 1, rng));
  append(p.accents, addMaterials(world, spec, MaterialKind::kConcrete, 1, rng));
  append(p.accents, addMaterials(world, spec, MaterialKind::kMarble, 1, rng));
  append(p.corridorAccents, addMaterials(world, spec, MaterialKind::kConcrete, 1, rng));
  append(p.corridorAccents, addMaterials(world, spec, MaterialKind::kBrick, 1, rng));
  append(p.corridorAccents, addMaterials(world, spec, MaterialKind::kBlocks, 1, rng));
  append(p.roomFloors, addMaterials(world, spec, MaterialKind::kCarpet, 3, rng));
  append(p.roomFloors, addMaterials(world, spec, MaterialKind::kParquet, 2, rng));
  append(p.roomFloors, addMaterials(world, spec, MaterialKind::kFloorTiles, 1, rng));
  append(p.corridorFloors, addMaterials(world, spec, MaterialKind::kLinoleum, 1, rng));
  append(p.corridorFloors, addMaterials(world, spec, MaterialKind::kFloorTiles, 1, rng));
  p.ceilings = addMaterials(world, spec, MaterialKind::kCeilingTiles, 2, rng);
  p.bookshelves = addMaterials(world, spec, MaterialKind::kBookshelf, 3, rng);
  p.cabinets = addMaterials(world, spec, MaterialKind::kCabinet, 3, rng);
  p.woods = addMaterials(world, spec, MaterialKind::kWood, 3, rng);
  p.fabrics = addMaterials(world, spec, MaterialKind::kFabric, 2, rng);
  p.foliage = addMaterials(world, spec, MaterialKind::kFoliage, 2, rng);
  p.metals = addMaterials(world, spec, MaterialKind::kMetal, 2, rng);
  p.facade = addMaterials(world, spec, MaterialKind::kConcrete, 1, rng).front();
  return p;
}

void assignThemes(Context& ctx, Rng& rng) {
  const BuildingSpec& spec = ctx.spec;
  const Palette& p = ctx.palette;
  // One paint and one floor for all corridors, as a building's common areas usually share them.
  const int corridorPaint = rng.pick(p.paints);
  const int corridorFloor = spec.plainCorridors ? p.corridorFloors.front() : rng.pick(p.corridorFloors);
  for (Area& area : ctx.building.areas) {
    Theme t;
    const bool corridor = area.kind == AreaKind::kCorridor;
    if (corridor) {
      t.paint = corridorPaint;
      t.accent = rng.pick(p.corridorAccents);
      t.floor = corridorFloor;
      // A plain corridor has a plain (plaster) ceiling: ceiling-tile grids would give the
      // camera a texture the scenario means to withhold.
      t.ceiling = spec.plainCorridors ? p.plasters.front() : rng.pick(p.ceilings);
      area.plain = spec.plainCorridors;
    } else {
      t.paint = rng.pick(p.paints);
      t.accent = rng.pick(p.accents);
      t.floor = rng.pick(p.roomFloors);
      t.ceiling = rng.chance(0.8) ? rng.pick(p.ceilings) : rng.pick(p.plasters);
      area.plain = rng.chance(spec.plainWallShare / 3.0);
    }
    for (int d = 0; d < 4; ++d) {
      const double accentChance = corridor ? 0.3 : 1.0 - spec.plainWallShare;
      t.plainSide[d] = area.plain || !rng.chance(accentChance);
      t.shiftS[d] = static_cast<float>(rng.uniform(0.0, 4.0));
      t.shiftT[d] = static_cast<float>(rng.uniform(0.0, 4.0));
    }
    ctx.themes.push_back(t);
  }
}

float faceShade(const Eigen::Vector2d& normal) {
  // A fixed main light direction in the plan (windows, ceiling lights): Lambert-like, never
  // dark, and the same from every viewpoint so the stereo pair stays photo-consistent.
  const Eigen::Vector2d light(std::cos(0.61), std::sin(0.61));
  return static_cast<float>(0.78 + 0.22 * (0.5 + 0.5 * normal.dot(light)));
}

}  // namespace rtabmap::sim::detail

#pragma once
// Procedural materials: the repeating surfaces of the simulated building (paint, bricks,
// concrete, wood panels, wallpaper, tiles, carpet, parquet, ceiling tiles, bookshelves,
// cabinets, ...). Each is a seamless square tile, by default 512 texels at 128 texels per metre
// (4 m x 4 m before it repeats), generated texel by texel from a seed.
//
// Like a real building, the same material recurs in many rooms (with another offset, so another
// part of the tile shows), which gives repeated-but-not-identical patterns; unique pictures
// (posters, doors, ...) are decals (Decals.h). Paint, plaster and linoleum are deliberately
// (almost) textureless: they are the stretches where visual odometry struggles.
//
// Texel (i, j) is at x = (i + 0.5) / texelsPerMetre along the surface, y = (j + 0.5) /
// texelsPerMetre downwards (rows go down, as heights go down on a wall).
#include <opencv2/core/mat.hpp>
#include <opencv2/core/matx.hpp>

#include <cstdint>
#include <string>

#include "rtabmap_core/sim/Texture.h"

namespace rtabmap::sim {

class Rng;

enum class MaterialKind {
  kPaint,         // flat paint: textureless
  kPlaster,       // soft low-contrast blotches: nearly textureless
  kBrick,         // running-bond bricks with mortar
  kBlocks,        // painted concrete blocks
  kWoodPanels,    // vertical planks with grain and joints
  kWallpaper,     // a repeated motif
  kWallTiles,     // small ceramic tiles with grout
  kConcrete,      // cast concrete: mottling, pores, form-tie holes, panel seams
  kMarble,        // veined stone
  kCarpet,        // carpet tiles, alternating pile direction
  kParquet,       // wooden strips
  kFloorTiles,    // large floor tiles with grout
  kLinoleum,      // corridor floor: faint speckles, nearly textureless
  kCeilingTiles,  // suspended ceiling grid with light panels
  kBookshelf,     // books on shelves
  kCabinet,       // drawers with handles
  kWood,          // furniture wood grain
  kFabric,        // upholstery weave with a check pattern
  kFoliage,       // plant leaves
  kMetal,         // brushed metal
};
const char* materialName(MaterialKind kind);
// Paint, plaster and linoleum: surfaces that give a feature detector next to nothing.
bool isTextureless(MaterialKind kind);

struct MaterialSpec {
  MaterialKind kind = MaterialKind::kPaint;
  uint32_t seed = 0;
  cv::Vec3f colour{200.0f, 200.0f, 200.0f};  // main colour, BGR 0..255
  cv::Vec3f accent{120.0f, 120.0f, 120.0f};  // second colour: mortar, grout, motif, grain
};

// A spec of that kind with colours that suit it (brick reds, wood browns, pastel paints...).
MaterialSpec randomMaterialSpec(MaterialKind kind, Rng& rng);
// Materials that cover metres of floor, ceiling or wall with a regular structure (courses,
// tiles, grids, planks, cast or speckled surfaces): tiled at the texture's period, a camera
// moved by a multiple of it would see exactly the same picture, so the building gives them
// several tile variants (see below). Paint and plaster (featureless), wallpaper (a printed
// repeat, periodic in reality too) and furniture materials (small faces) have one.
bool variesPerTile(MaterialKind kind);
// The tile image, CV_8UC3, size x size (a power of two). `variant` 0 is the material's tile;
// another variant keeps its structure (joints, grout, courses, grid, colours) and draws its
// random details (noise, specks, pores, per-brick or per-tile shades) again, so that variants
// placed side by side in any order meet without a seam (Procedural.h).
cv::Mat generateMaterialImage(const MaterialSpec& spec, int size = 512, float texelsPerMetre = 128.0f, int variant = 0);
// The material's colour at (x, y) metres on a tile of that size and density (what texel
// generation evaluates at texel centres). Periodic: adding the tile's period (size /
// texelsPerMetre) to x or y gives the same colour. Slow (sets the generator up per call): tests.
cv::Vec3f materialColourAt(const MaterialSpec& spec, float x, float y, int size = 512, float texelsPerMetre = 128.0f,
                           int variant = 0);
// The tile as a wrapping texture with its mip chain; with `variants` > 1, variants 0 ..
// variants - 1, one of which shows on each tile of a surface (Texture::variantAt).
Texture makeMaterialTexture(const MaterialSpec& spec, int size = 512, float texelsPerMetre = 128.0f, int variants = 1);

}  // namespace rtabmap::sim

// Material generators. Each material is a function colour(x, y) of the position on the tile in
// metres, evaluated at every texel; every repeating feature (bricks, planks, tiles, books) uses
// a whole number of repeats per tile, so the tile wraps without a seam.
//
// Variants (Tile::variant, 0 = the plain tile): the same structure (courses, joints, grout,
// grid) with other random draws inside it: noise lattices and cellular points through
// Procedural.h's variant rule (the border's values are shared, so variants meet seamlessly),
// and per-unit shades through Tile::unitSeed. A unit that straddles the tile's border (column 0
// of a staggered course) keeps variant 0's draws, or its two halves would differ.
#include "rtabmap_core/sim/Materials.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "rtabmap_core/sim/Procedural.h"
#include "rtabmap_core/sim/Random.h"

namespace rtabmap::sim {

namespace {

using Colour = cv::Vec3f;
using TexelFunction = std::function<Colour(float x, float y)>;
constexpr float kTwoPi = 6.28318530718f;

// The tile being generated: its period in metres and a few helpers in metres.
struct Tile {
  float period;
  uint32_t seed;
  uint32_t variant = 0;
  // Repeats of a feature of about `size` metres in one tile (at least 1; `even` for patterns
  // that alternate, like staggered brick rows).
  int repeats(float size, bool even = false) const {
    int n = std::max(1, static_cast<int>(std::lround(period / size)));
    if (even && (n % 2)) n += 1;
    return n;
  }
  // Fractal noise whose finest features are about cellX by cellY metres (this variant's, or
  // variant 0's when not `varied`).
  float noise(float x, float y, float cellX, float cellY, int octaves, uint32_t salt, bool varied = true) const {
    const int nx = repeats(cellX);
    const int ny = repeats(cellY);
    return fbm(x * nx / period, y * ny / period, octaves, nx, ny, seed ^ salt, 0.5f, varied ? variant : 0u);
  }
  // Cellular pattern with `cells` cells per tile, this variant's.
  float cells(float x, float y, int count, uint32_t salt, uint32_t* cellHash) const {
    return cellular(x * count / period, y * count / period, count, seed ^ salt, cellHash, variant);
  }
  // Seed of the per-unit draws (a brick's shade, a tile's tint): this variant's, or variant 0's
  // for a unit `shared` with the next tile.
  uint32_t unitSeed(bool shared = false) const { return shared ? seed : variantSeed(1, 1, seed, variant); }
};

Colour scaled(const Colour& c, float k) { return c * k; }

// ---- walls --------------------------------------------------------------------------------

TexelFunction paint(const MaterialSpec& m, const Tile& tile) {
  // Under half a grey level of variation: a camera sees a flat colour.
  return [=](float x, float y) {
    return scaled(m.colour, 1.0f + 0.004f * (tile.noise(x, y, 0.8f, 0.8f, 1, 1) - 0.5f));
  };
}

TexelFunction plaster(const MaterialSpec& m, const Tile& tile) {
  return [=](float x, float y) {
    const float n = tile.noise(x, y, 0.35f, 0.35f, 2, 2);
    return scaled(m.colour, 0.97f + 0.06f * n);
  };
}

// Staggered courses (bricks, blocks): the unit's local position and its identity.
struct Course {
  float lx, ly;  // position inside the unit, metres
  int col, row;
};
// `rows` is even, so wrapping the row keeps the stagger's parity.
Course course(float x, float y, float unitW, float unitH, int cols, int rows) {
  Course c;
  const int row = static_cast<int>(std::floor(y / unitH));
  c.row = wrapi(row, rows);
  const float xo = x + ((c.row & 1) ? 0.5f * unitW : 0.0f);
  const int col = static_cast<int>(std::floor(xo / unitW));
  c.col = wrapi(col, cols);
  c.lx = xo - static_cast<float>(col) * unitW;
  c.ly = y - static_cast<float>(row) * unitH;
  return c;
}

TexelFunction brick(const MaterialSpec& m, const Tile& tile) {
  const int rows = tile.repeats(0.076f, true);
  const int cols = tile.repeats(0.225f);
  const float h = tile.period / rows;
  const float w = tile.period / cols;
  const float mortar = 0.012f;
  return [=](float x, float y) {
    const Course c = course(x, y, w, h, cols, rows);
    const float grain = tile.noise(x, y, 0.02f, 0.02f, 2, 3);
    if (c.lx < mortar || c.ly < mortar) return scaled(m.accent, 0.88f + 0.2f * grain);
    const uint32_t id = hash2D(c.col, c.row, tile.unitSeed(c.col == 0));  // column 0 straddles the border
    Colour b = scaled(m.colour, 0.74f + 0.42f * hashUnit(id));
    b[0] *= 0.9f + 0.2f * hashUnit(id * 7u + 1u);  // a little hue drift between bricks
    const float edge = std::min({c.lx - mortar, w - c.lx, c.ly - mortar, h - c.ly});
    const float wear = edge < 0.008f ? 0.82f : 1.0f;
    return scaled(b, wear * (0.82f + 0.3f * grain));
  };
}

TexelFunction blocks(const MaterialSpec& m, const Tile& tile) {
  const int rows = tile.repeats(0.2f, true);
  const int cols = tile.repeats(0.4f);
  const float h = tile.period / rows;
  const float w = tile.period / cols;
  const float joint = 0.012f;
  const int poreCells = tile.repeats(0.03f);
  return [=](float x, float y) {
    const Course c = course(x, y, w, h, cols, rows);
    if (c.lx < joint || c.ly < joint) return scaled(m.accent, 0.95f);
    uint32_t cell = 0;
    const float d = tile.cells(x, y, poreCells, 5u, &cell);
    const float pore = (d < 0.16f && hashUnit(cell) < 0.35f) ? 0.72f : 1.0f;
    const float shade = 0.94f + 0.08f * hashUnit(hash2D(c.col, c.row, tile.unitSeed(c.col == 0)));
    return scaled(m.colour, shade * pore * (0.95f + 0.08f * tile.noise(x, y, 0.05f, 0.05f, 2, 6)));
  };
}

TexelFunction woodPanels(const MaterialSpec& m, const Tile& tile) {
  const int planks = tile.repeats(0.14f);
  const float w = tile.period / planks;
  const int joints = tile.repeats(1.0f);
  const float jointPitch = tile.period / joints;
  return [=](float x, float y) {
    const int p = static_cast<int>(std::floor(x / w));
    const float lx = x - p * w;
    if (lx < 0.008f) return scaled(m.accent, 0.45f);
    // A plank runs on into the next tile: its colour is shared, its joints are the variant's.
    const uint32_t id = hash2D(wrapi(p, planks), 0, tile.seed);
    // No joint on the tile's border, where the next tile (another variant) would not go on with it.
    const float jointOffset = 0.01f + hashUnit(hash2D(wrapi(p, planks), 0, tile.unitSeed())) * (jointPitch - 0.02f);
    if (wrapf(y + jointOffset, jointPitch) < 0.008f) return scaled(m.accent, 0.5f);
    const float warp = tile.noise(x, y, 0.04f, 0.5f, 3, 7);
    const float rings = 0.5f + 0.5f * std::sin(kTwoPi * (lx / w * 4.0f + 5.0f * warp));
    const Colour base = scaled(m.colour, 0.85f + 0.3f * hashUnit(id * 3u + 2u));
    return mixColour(base, m.accent, 0.45f * rings * rings * rings);
  };
}

TexelFunction wallpaper(const MaterialSpec& m, const Tile& tile) {
  const int n = tile.repeats(0.25f, true);
  const float cell = tile.period / n;
  const int motif = static_cast<int>(tile.seed % 4u);
  return [=](float x, float y) {
    const int cy = static_cast<int>(std::floor(y / cell));
    const float xo = (motif == 1 && (cy & 1)) ? x + 0.5f * cell : x;  // dots in a hex layout
    const float u = wrapf(xo, cell) / cell;
    const float v = wrapf(y, cell) / cell;
    float ink = 0.0f;
    switch (motif) {
      case 0: {  // diamonds with an outline
        const float d = std::fabs(u - 0.5f) + std::fabs(v - 0.5f);
        ink = d < 0.3f ? 1.0f : (d > 0.36f && d < 0.41f ? 0.6f : 0.0f);
        break;
      }
      case 1: {  // dots
        ink = std::hypot(u - 0.5f, v - 0.5f) < 0.22f ? 1.0f : 0.0f;
        break;
      }
      case 2: {  // stripes with a five-petal flower between them
        const float du = u - 0.5f;
        const float dv = v - 0.5f;
        const float r = std::hypot(du, dv);
        const float petals = 0.12f + 0.07f * std::cos(5.0f * std::atan2(dv, du));
        ink = (u < 0.08f) ? 0.8f : (r < petals ? 1.0f : 0.0f);
        break;
      }
      default: {  // damask-like lobes
        const float s = std::sin(kTwoPi * u) * std::sin(kTwoPi * v) +
                        0.5f * std::cos(2.0f * kTwoPi * (u + v));
        ink = s > 0.55f ? 1.0f : 0.0f;
        break;
      }
    }
    const Colour paper = scaled(m.colour, 0.97f + 0.05f * tile.noise(x, y, 0.1f, 0.1f, 2, 8));
    return mixColour(paper, m.accent, ink * 0.85f);
  };
}

TexelFunction wallTiles(const MaterialSpec& m, const Tile& tile) {
  const int n = tile.repeats(0.15f);
  const float cell = tile.period / n;
  return [=](float x, float y) {
    const int tx = static_cast<int>(std::floor(x / cell));
    const int ty = static_cast<int>(std::floor(y / cell));
    const float lx = x - tx * cell;
    const float ly = y - ty * cell;
    if (lx < 0.009f || ly < 0.009f) return m.accent;
    const uint32_t id = hash2D(wrapi(tx, n), wrapi(ty, n), tile.unitSeed());
    const Colour base = hashUnit(id) < 0.07f ? mixColour(m.colour, hsv(hashUnit(id * 5u) * 360.0f, 0.5f, 0.6f), 0.7f)
                                             : m.colour;
    const float glaze = 0.96f + 0.08f * (1.0f - (lx + ly) / (2.0f * cell));
    return scaled(base, glaze * (0.95f + 0.1f * hashUnit(id * 3u + 1u)));
  };
}

TexelFunction concrete(const MaterialSpec& m, const Tile& tile) {
  const int poreCells = tile.repeats(0.03f);
  const int ties = tile.repeats(0.6f);
  const float tiePitch = tile.period / ties;
  const int seams = tile.repeats(1.2f);
  const float seamPitch = tile.period / seams;
  // Vertical seams about every second horizontal one, a whole number per tile as well.
  const float panelPitch = tile.period / tile.repeats(2.0f * seamPitch);
  return [=](float x, float y) {
    float k = 0.78f + 0.4f * tile.noise(x, y, 0.06f, 0.06f, 5, 9);
    uint32_t cell = 0;
    const float d = tile.cells(x, y, poreCells, 10u, &cell);
    if (d < 0.13f && hashUnit(cell) < 0.4f) k *= 0.6f;
    const float tx = wrapf(x, tiePitch) - 0.5f * tiePitch;
    const float ty = wrapf(y, tiePitch) - 0.5f * tiePitch;
    if (std::hypot(tx, ty) < 0.013f) k *= 0.35f;
    if (wrapf(y, seamPitch) < 0.007f || wrapf(x, panelPitch) < 0.007f) k *= 0.7f;
    return scaled(m.colour, k);
  };
}

TexelFunction marble(const MaterialSpec& m, const Tile& tile) {
  const float kx = 2.0f;  // whole numbers of vein bands per tile keep it seamless
  const float ky = 1.0f;
  return [=](float x, float y) {
    const float n = tile.noise(x, y, 0.08f, 0.08f, 5, 11);
    const float phase = kTwoPi * (kx * x + ky * y) / tile.period + 9.0f * n;
    const float vein = std::pow(1.0f - std::fabs(std::sin(phase)), 10.0f);
    const Colour base = scaled(m.colour, 0.93f + 0.1f * tile.noise(x, y, 0.3f, 0.3f, 2, 12));
    return mixColour(base, m.accent, 0.8f * vein);
  };
}

// ---- floors and ceilings ---------------------------------------------------------------------

TexelFunction carpet(const MaterialSpec& m, const Tile& tile) {
  const int n = tile.repeats(0.5f);
  const float cell = tile.period / n;
  const int fleckCells = tile.repeats(0.04f);
  return [=](float x, float y) {
    const int tx = static_cast<int>(std::floor(x / cell));
    const int ty = static_cast<int>(std::floor(y / cell));
    const float lx = x - tx * cell;
    const float ly = y - ty * cell;
    if (lx < 0.005f || ly < 0.005f) return scaled(m.colour, 0.7f);
    const float along = ((tx + ty) & 1) ? lx : ly;  // pile direction alternates per tile
    const float ribs = 0.5f + 0.5f * std::sin(kTwoPi * along / (cell / std::round(cell / 0.05f)));
    uint32_t fleck = 0;
    const float d = tile.cells(x, y, fleckCells, 13u, &fleck);
    if (d < 0.12f && hashUnit(fleck) < 0.5f) return m.accent;
    const float tileShade = 0.95f + 0.1f * hashUnit(hash2D(wrapi(tx, n), wrapi(ty, n), tile.unitSeed()));
    return scaled(m.colour, tileShade * (0.9f + 0.1f * ribs) * (0.92f + 0.16f * tile.noise(x, y, 0.02f, 0.02f, 1, 14)));
  };
}

TexelFunction parquet(const MaterialSpec& m, const Tile& tile) {
  const int across = tile.repeats(0.07f, true);
  const int along = tile.repeats(0.42f);
  const float h = tile.period / across;
  const float w = tile.period / along;
  return [=](float x, float y) {
    const Course c = course(x, y, w, h, along, across);
    if (c.lx < 0.006f || c.ly < 0.004f) return scaled(m.accent, 0.6f);
    // Column 0 straddles the border: variant 0's draws, and its grain (shifted along x, it would
    // not meet the next tile's at the border).
    const uint32_t id = hash2D(c.col, c.row, tile.unitSeed(c.col == 0));
    const float grain = tile.noise(x + hashUnit(id), y, 0.6f, 0.012f, 3, 15, c.col != 0);
    const Colour base = scaled(m.colour, 0.8f + 0.35f * hashUnit(id * 3u + 1u));
    return mixColour(base, m.accent, 0.35f * grain);
  };
}

TexelFunction floorTiles(const MaterialSpec& m, const Tile& tile) {
  const int n = tile.repeats(0.45f);
  const float cell = tile.period / n;
  return [=](float x, float y) {
    const int tx = static_cast<int>(std::floor(x / cell));
    const int ty = static_cast<int>(std::floor(y / cell));
    if (x - tx * cell < 0.01f || y - ty * cell < 0.01f) return m.accent;
    const float shade = 0.92f + 0.16f * hashUnit(hash2D(wrapi(tx, n), wrapi(ty, n), tile.unitSeed()));
    return scaled(m.colour, shade * (0.88f + 0.22f * tile.noise(x, y, 0.05f, 0.05f, 3, 16)));
  };
}

TexelFunction linoleum(const MaterialSpec& m, const Tile& tile) {
  const int specks = tile.repeats(0.02f);
  return [=](float x, float y) {
    uint32_t cell = 0;
    const float d = tile.cells(x, y, specks, 17u, &cell);
    const float speck = (d < 0.15f && hashUnit(cell) < 0.25f) ? (hashUnit(cell * 3u) < 0.5f ? 0.9f : 1.08f) : 1.0f;
    return scaled(m.colour, speck * (0.985f + 0.03f * tile.noise(x, y, 0.4f, 0.4f, 2, 18)));
  };
}

TexelFunction ceilingTiles(const MaterialSpec& m, const Tile& tile) {
  // Lights sit on every third tile across and every second along: a multiple of 6 tiles per
  // repeat keeps that pattern seamless.
  const int n = 6 * std::max(1, static_cast<int>(std::lround(tile.period / 0.6f / 6.0f)));
  const float cell = tile.period / n;
  const int fissures = tile.repeats(0.025f);
  // Which tiles of the 3 x 2 pattern hold the lights: another choice in each of the first six
  // variants, so the lights keep their spacing inside a tile but not from tile to tile.
  const uint32_t phase = (4u + tile.variant) % 6u;
  const int lightX = static_cast<int>(phase % 3u);
  const int lightY = static_cast<int>(phase / 3u);
  return [=](float x, float y) {
    const int tx = static_cast<int>(std::floor(x / cell));
    const int ty = static_cast<int>(std::floor(y / cell));
    const float lx = x - tx * cell;
    const float ly = y - ty * cell;
    if (lx < 0.022f || ly < 0.022f) return m.accent;  // the metal T-bar grid
    if (wrapi(tx, 3) == lightX && wrapi(ty, 2) == lightY) {  // a light panel with louvres
      const bool louvre = wrapf(lx, cell / 6.0f) < 0.012f || wrapf(ly, cell / 6.0f) < 0.012f;
      return louvre ? Colour(215, 215, 215) : Colour(250, 250, 250);
    }
    uint32_t cellHash = 0;
    const float d = tile.cells(x, y, fissures, 19u, &cellHash);
    const float k = (d < 0.18f && hashUnit(cellHash) < 0.5f) ? 0.84f : 1.0f;
    return scaled(m.colour, k * (0.95f + 0.06f * tile.noise(x, y, 0.15f, 0.15f, 2, 20)));
  };
}

// ---- furniture -------------------------------------------------------------------------------

TexelFunction bookshelf(const MaterialSpec& m, const Tile& tile) {
  struct Book {
    float x0, x1, height;
    Colour colour;
    float band0, band1;  // lighter title bands, as fractions of the height
  };
  const int shelves = tile.repeats(0.36f);
  const float shelfH = tile.period / shelves;
  const int sections = tile.repeats(0.8f);
  const float sectionW = tile.period / sections;
  const float board = 0.025f;
  const float upright = 0.02f;
  // Books are laid out once per (shelf, section), left to right, until the section is full.
  std::vector<std::vector<Book>> rows(static_cast<size_t>(shelves * sections));
  Rng rng(tile.seed, "bookshelf");
  for (auto& row : rows) {
    float x = upright + rng.uniform(0.0, 0.03);
    while (true) {
      const float w = static_cast<float>(rng.uniform(0.018, 0.055));
      if (x + w > sectionW - 0.01f) break;
      Book b;
      b.x0 = x;
      b.x1 = x + w;
      b.height = static_cast<float>(rng.uniform(0.17, shelfH - board - 0.02));
      const float hue = static_cast<float>(rng.uniform(0, 360));  // one draw per statement: a fixed order
      const float saturation = static_cast<float>(rng.uniform(0.3, 0.85));
      b.colour = hsv(hue, saturation, static_cast<float>(rng.uniform(0.25, 0.85)));
      b.band0 = static_cast<float>(rng.uniform(0.1, 0.3));
      b.band1 = static_cast<float>(rng.uniform(0.6, 0.85));
      row.push_back(b);
      x = b.x1 + (rng.chance(0.1) ? static_cast<float>(rng.uniform(0.02, 0.12)) : 0.002f);
    }
  }
  return [=](float x, float y) {
    const int shelf = static_cast<int>(std::floor(y / shelfH));
    const int section = static_cast<int>(std::floor(x / sectionW));
    const float lx = x - section * sectionW;
    const float fromBoard = (shelf + 1) * shelfH - board - y;  // height above the shelf board
    if (lx < upright) return scaled(m.colour, 0.9f);
    if (fromBoard < 0.0f) return scaled(m.colour, 1.0f - 0.15f * (-fromBoard / board));
    const auto& row = rows[static_cast<size_t>(wrapi(shelf, shelves) * sections + wrapi(section, sections))];
    auto it = std::upper_bound(row.begin(), row.end(), lx, [](float v, const Book& b) { return v < b.x1; });
    if (it == row.end() || lx < it->x0 || fromBoard > it->height) return scaled(m.colour, 0.28f);
    const float f = fromBoard / it->height;
    const float edge = std::min(lx - it->x0, it->x1 - lx);
    Colour c = it->colour * (edge < 0.003f ? 0.7f : 1.0f);
    if (std::fabs(f - it->band0) < 0.03f || std::fabs(f - it->band1) < 0.02f) c = mixColour(c, Colour(200, 215, 225), 0.7f);
    return c;
  };
}

TexelFunction cabinet(const MaterialSpec& m, const Tile& tile) {
  const int cols = tile.repeats(0.5f);
  const int rows = tile.repeats(0.3f);
  const float w = tile.period / cols;
  const float h = tile.period / rows;
  return [=](float x, float y) {
    const float lx = wrapf(x, w);
    const float ly = wrapf(y, h);
    if (lx < 0.012f || ly < 0.012f) return scaled(m.colour, 0.4f);  // the gap between drawers
    if (ly > 0.04f && ly < 0.065f && std::fabs(lx - 0.5f * w) < 0.075f) return m.accent;  // handle
    if (ly > 0.1f && ly < 0.15f && lx > 0.05f && lx < 0.15f) return Colour(235, 240, 240);  // label holder
    return scaled(m.colour, 0.95f + 0.08f * tile.noise(x, y, 1.0f, 0.01f, 2, 21));
  };
}

TexelFunction wood(const MaterialSpec& m, const Tile& tile) {
  return [=](float x, float y) {
    const float warp = tile.noise(x, y, 0.5f, 0.03f, 3, 22);
    const float lines = 0.5f + 0.5f * std::sin(kTwoPi * (y * tile.repeats(0.04f) / tile.period + 3.0f * warp));
    return mixColour(m.colour, m.accent, 0.55f * lines * lines);
  };
}

TexelFunction fabric(const MaterialSpec& m, const Tile& tile) {
  const int checks = tile.repeats(0.12f);
  const int threads = tile.repeats(0.03f);
  return [=](float x, float y) {
    const int cx = static_cast<int>(std::floor(x * checks / tile.period));
    const int cy = static_cast<int>(std::floor(y * checks / tile.period));
    const Colour base = ((cx + cy) & 1) ? m.colour : mixColour(m.colour, m.accent, 0.35f);
    const float weave = std::sin(kTwoPi * x * threads / tile.period) * std::sin(kTwoPi * y * threads / tile.period);
    return scaled(base, 0.94f + 0.06f * weave);
  };
}

TexelFunction foliage(const MaterialSpec& m, const Tile& tile) {
  const int leaves = tile.repeats(0.06f);
  return [=](float x, float y) {
    uint32_t leaf = 0;
    const float d = cellular(x * leaves / tile.period, y * leaves / tile.period, leaves, tile.seed ^ 23u, &leaf);
    if (d > 0.5f) return scaled(m.accent, 0.4f);
    const Colour c = hsv(80.0f + 50.0f * hashUnit(leaf), 0.55f + 0.3f * hashUnit(leaf * 3u), 0.25f + 0.45f * hashUnit(leaf * 7u));
    return scaled(c, 1.0f - 0.5f * d);
  };
}

TexelFunction metal(const MaterialSpec& m, const Tile& tile) {
  return [=](float x, float y) {
    return scaled(m.colour, 0.9f + 0.16f * tile.noise(x, y, 1.0f, 0.008f, 2, 24));
  };
}

TexelFunction generatorFor(const MaterialSpec& m, const Tile& tile) {
  switch (m.kind) {
    case MaterialKind::kPaint: return paint(m, tile);
    case MaterialKind::kPlaster: return plaster(m, tile);
    case MaterialKind::kBrick: return brick(m, tile);
    case MaterialKind::kBlocks: return blocks(m, tile);
    case MaterialKind::kWoodPanels: return woodPanels(m, tile);
    case MaterialKind::kWallpaper: return wallpaper(m, tile);
    case MaterialKind::kWallTiles: return wallTiles(m, tile);
    case MaterialKind::kConcrete: return concrete(m, tile);
    case MaterialKind::kMarble: return marble(m, tile);
    case MaterialKind::kCarpet: return carpet(m, tile);
    case MaterialKind::kParquet: return parquet(m, tile);
    case MaterialKind::kFloorTiles: return floorTiles(m, tile);
    case MaterialKind::kLinoleum: return linoleum(m, tile);
    case MaterialKind::kCeilingTiles: return ceilingTiles(m, tile);
    case MaterialKind::kBookshelf: return bookshelf(m, tile);
    case MaterialKind::kCabinet: return cabinet(m, tile);
    case MaterialKind::kWood: return wood(m, tile);
    case MaterialKind::kFabric: return fabric(m, tile);
    case MaterialKind::kFoliage: return foliage(m, tile);
    case MaterialKind::kMetal: return metal(m, tile);
  }
  return paint(m, tile);
}

// Draws in statement order (function arguments have no evaluation order).
Colour randomHsv(Rng& rng, float h0, float h1, float s0, float s1, float v0, float v1) {
  const float h = static_cast<float>(rng.uniform(h0, h1));
  const float s = static_cast<float>(rng.uniform(s0, s1));
  return hsv(h, s, static_cast<float>(rng.uniform(v0, v1)));
}

}  // namespace

const char* materialName(MaterialKind kind) {
  switch (kind) {
    case MaterialKind::kPaint: return "paint";
    case MaterialKind::kPlaster: return "plaster";
    case MaterialKind::kBrick: return "brick";
    case MaterialKind::kBlocks: return "blocks";
    case MaterialKind::kWoodPanels: return "wood_panels";
    case MaterialKind::kWallpaper: return "wallpaper";
    case MaterialKind::kWallTiles: return "wall_tiles";
    case MaterialKind::kConcrete: return "concrete";
    case MaterialKind::kMarble: return "marble";
    case MaterialKind::kCarpet: return "carpet";
    case MaterialKind::kParquet: return "parquet";
    case MaterialKind::kFloorTiles: return "floor_tiles";
    case MaterialKind::kLinoleum: return "linoleum";
    case MaterialKind::kCeilingTiles: return "ceiling_tiles";
    case MaterialKind::kBookshelf: return "bookshelf";
    case MaterialKind::kCabinet: return "cabinet";
    case MaterialKind::kWood: return "wood";
    case MaterialKind::kFabric: return "fabric";
    case MaterialKind::kFoliage: return "foliage";
    case MaterialKind::kMetal: return "metal";
  }
  return "unknown";
}

bool isTextureless(MaterialKind kind) {
  return kind == MaterialKind::kPaint || kind == MaterialKind::kPlaster || kind == MaterialKind::kLinoleum;
}

MaterialSpec randomMaterialSpec(MaterialKind kind, Rng& rng) {
  MaterialSpec m;
  m.kind = kind;
  m.seed = rng.seed32();
  switch (kind) {
    case MaterialKind::kPaint:
      m.colour = randomHsv(rng, 0, 360, 0.04f, 0.32f, 0.68f, 0.94f);
      break;
    case MaterialKind::kPlaster:
      m.colour = randomHsv(rng, 20, 60, 0.0f, 0.15f, 0.75f, 0.92f);
      break;
    case MaterialKind::kBrick:
      m.colour = randomHsv(rng, 0, 25, 0.5f, 0.75f, 0.42f, 0.7f);
      m.accent = randomHsv(rng, 30, 50, 0.0f, 0.1f, 0.65f, 0.8f);
      break;
    case MaterialKind::kBlocks:
      m.colour = randomHsv(rng, 0, 360, 0.0f, 0.2f, 0.7f, 0.9f);
      m.accent = m.colour * 0.8f;
      break;
    case MaterialKind::kWoodPanels:
    case MaterialKind::kParquet:
    case MaterialKind::kWood:
      m.colour = randomHsv(rng, 18, 38, 0.4f, 0.7f, 0.4f, 0.78f);
      m.accent = m.colour * 0.55f;
      break;
    case MaterialKind::kWallpaper:
      m.colour = randomHsv(rng, 0, 360, 0.05f, 0.25f, 0.8f, 0.95f);
      m.accent = randomHsv(rng, 0, 360, 0.3f, 0.7f, 0.35f, 0.75f);
      break;
    case MaterialKind::kWallTiles:
      m.colour = randomHsv(rng, 0, 360, 0.0f, 0.2f, 0.82f, 0.96f);
      m.accent = randomHsv(rng, 0, 360, 0.0f, 0.05f, 0.45f, 0.65f);
      break;
    case MaterialKind::kConcrete:
      m.colour = randomHsv(rng, 0, 60, 0.0f, 0.08f, 0.55f, 0.75f);
      break;
    case MaterialKind::kMarble:
      m.colour = randomHsv(rng, 0, 60, 0.0f, 0.08f, 0.8f, 0.93f);
      m.accent = randomHsv(rng, 90, 220, 0.05f, 0.25f, 0.25f, 0.45f);
      break;
    case MaterialKind::kCarpet:
      m.colour = randomHsv(rng, 0, 360, 0.15f, 0.5f, 0.25f, 0.5f);
      m.accent = m.colour * 1.5f;
      break;
    case MaterialKind::kFloorTiles:
      m.colour = randomHsv(rng, 0, 360, 0.0f, 0.25f, 0.5f, 0.85f);
      m.accent = randomHsv(rng, 0, 60, 0.0f, 0.08f, 0.3f, 0.5f);
      break;
    case MaterialKind::kLinoleum:
      m.colour = randomHsv(rng, 0, 360, 0.08f, 0.3f, 0.5f, 0.7f);
      break;
    case MaterialKind::kCeilingTiles:
      m.colour = randomHsv(rng, 30, 60, 0.0f, 0.04f, 0.84f, 0.9f);
      m.accent = randomHsv(rng, 0, 60, 0.0f, 0.03f, 0.93f, 0.97f);
      break;
    case MaterialKind::kBookshelf:
      m.colour = randomHsv(rng, 18, 38, 0.3f, 0.6f, 0.35f, 0.7f);
      break;
    case MaterialKind::kCabinet:
      m.colour = rng.chance(0.5) ? randomHsv(rng, 0, 360, 0.0f, 0.08f, 0.55f, 0.85f)
                                 : randomHsv(rng, 0, 360, 0.3f, 0.6f, 0.35f, 0.7f);
      m.accent = randomHsv(rng, 0, 60, 0.0f, 0.05f, 0.2f, 0.85f);
      break;
    case MaterialKind::kFabric:
      m.colour = randomHsv(rng, 0, 360, 0.3f, 0.65f, 0.25f, 0.6f);
      m.accent = randomHsv(rng, 0, 360, 0.2f, 0.6f, 0.3f, 0.7f);
      break;
    case MaterialKind::kFoliage:
      m.colour = randomHsv(rng, 90, 130, 0.5f, 0.8f, 0.3f, 0.6f);
      m.accent = randomHsv(rng, 20, 40, 0.5f, 0.7f, 0.15f, 0.3f);
      break;
    case MaterialKind::kMetal:
      m.colour = randomHsv(rng, 180, 230, 0.0f, 0.08f, 0.5f, 0.8f);
      break;
  }
  return m;
}

bool variesPerTile(MaterialKind kind) {
  switch (kind) {
    case MaterialKind::kBrick:
    case MaterialKind::kBlocks:
    case MaterialKind::kWoodPanels:
    case MaterialKind::kWallTiles:
    case MaterialKind::kConcrete:
    case MaterialKind::kMarble:
    case MaterialKind::kCarpet:
    case MaterialKind::kParquet:
    case MaterialKind::kFloorTiles:
    case MaterialKind::kLinoleum:
    case MaterialKind::kCeilingTiles:
      return true;
    default:
      return false;
  }
}

cv::Mat generateMaterialImage(const MaterialSpec& spec, int size, float texelsPerMetre, int variant) {
  cv::Mat image(size, size, CV_8UC3);
  const Tile tile{static_cast<float>(size) / texelsPerMetre, spec.seed, static_cast<uint32_t>(variant)};
  const TexelFunction colourAt = generatorFor(spec, tile);
  // Rows are independent: parallel, and still the same texels whatever the thread count.
  cv::parallel_for_(cv::Range(0, size), [&](const cv::Range& range) {
    for (int j = range.start; j < range.end; ++j) {
      cv::Vec3b* row = image.ptr<cv::Vec3b>(j);
      const float y = (static_cast<float>(j) + 0.5f) / texelsPerMetre;
      for (int i = 0; i < size; ++i) {
        row[i] = toBgr8(colourAt((static_cast<float>(i) + 0.5f) / texelsPerMetre, y));
      }
    }
  });
  return image;
}

cv::Vec3f materialColourAt(const MaterialSpec& spec, float x, float y, int size, float texelsPerMetre, int variant) {
  const Tile tile{static_cast<float>(size) / texelsPerMetre, spec.seed, static_cast<uint32_t>(variant)};
  return generatorFor(spec, tile)(x, y);
}

Texture makeMaterialTexture(const MaterialSpec& spec, int size, float texelsPerMetre, int variants) {
  std::vector<cv::Mat> images;
  for (int v = 0; v < std::max(1, variants); ++v) images.push_back(generateMaterialImage(spec, size, texelsPerMetre, v));
  return Texture(images, true, texelsPerMetre, spec.seed);
}

}  // namespace rtabmap::sim

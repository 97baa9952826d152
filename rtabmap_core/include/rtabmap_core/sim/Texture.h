#pragma once
// A colour texture with its mip chain, for sampling without aliasing at any distance.
//
// Distant surfaces shrink many texels into one pixel; sampling the full-resolution image there
// would turn fine patterns into pixel noise, which a feature detector reads as corners that no
// real camera would see (and that change from frame to frame). Each level halves the previous
// one with a 2x2 box filter, and the renderer picks the level whose texels are about one pixel
// wide (see levelFor), then samples it bilinearly.
//
// Two kinds: materials repeat (wrap) and must have power-of-two sizes, so wrapping is a mask;
// decals (posters, doors, windows) are single pictures clamped at their border.
//
// A wrapping texture may hold several tile variants (same size, made to meet seamlessly in any
// order: Materials.h): the surface's plane is cut into tiles of the picture's size, and each tile
// shows the variant variantAt(key, tile x, tile y) picks, a hash of the tile's integer indices
// and of the surface's key (SurfaceMaterial::variantKey). A large surface then does not show the
// same picture again one period away, as no real floor or brick wall does.
//
// Texel coordinates: (s, t) in level-0 texels, s along the columns, t along the rows; texel
// (i, j) covers [i, i+1) x [j, j+1), its centre at (i + 0.5, j + 0.5).
//
// Storage is transposed (one row per picture column): the renderer walks down image columns,
// which on a wall is down one texture column, so the texels it reads next are contiguous in
// memory instead of one texture row apart.
#include <opencv2/core/mat.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "rtabmap_core/sim/Random.h"

namespace rtabmap::sim {

// floor() without a libm call (the default x86-64 target has no SSE4.1 rounding).
inline int fastFloor(float x) {
  const int i = static_cast<int>(x);
  return (x < static_cast<float>(i)) ? i - 1 : i;
}

// One mip level, as raw pointers for the renderer's inner loop.
struct TextureLevel {
  const uint8_t* data = nullptr;  // transposed: texel (i, j) at data + i * step + 3 * j
  int width = 0;
  int height = 0;
  size_t step = 0;      // bytes per stored row (= per picture column)
  float scaleX = 1.0f;  // level-0 texels -> this level's texels (1 / 2^level for materials;
  float scaleY = 1.0f;  //   the exact size ratio for decals, whose odd sizes round up)
  bool wrap = false;
  int shiftX = 0;       // wrapping: log2 of width and height (texel index >> shift = tile index)
  int shiftY = 0;
};

class Texture {
 public:
  Texture() = default;
  // image: CV_8UC3 (BGR). A wrapping texture needs power-of-two width and height
  // (std::invalid_argument otherwise). texelsPerMetre: how large it appears on surfaces.
  Texture(const cv::Mat& image, bool wrap, float texelsPerMetre);
  // A wrapping texture with tile variants (at least one, all the same power-of-two size);
  // `salt` makes two textures pick their variants independently on the same surface.
  Texture(const std::vector<cv::Mat>& variants, bool wrap, float texelsPerMetre, uint32_t salt = 0);

  bool empty() const { return levels_.empty(); }
  int levels() const { return levelCount_; }
  int variants() const { return variantCount_; }
  // The picture of a level of a variant, in the usual orientation (a copy).
  cv::Mat image(int level = 0, int variant = 0) const;
  const TextureLevel& level(int level, int variant = 0) const {
    return views_[static_cast<size_t>(variant * levelCount_ + level)];
  }
  // The variant shown on tile (tileX, tileY) (level-0 texel index >> level(0).shiftX, ...) of a
  // surface with that key: a hash, so the same on every run and every thread.
  int variantAt(uint32_t key, int tileX, int tileY) const {
    if (variantCount_ == 1) return 0;
    // Multiply-shift instead of a modulo: no division in the renderer's inner loop.
    const uint64_t h = hash2D(tileX, tileY, key ^ salt_);
    return static_cast<int>((h * static_cast<uint64_t>(variantCount_)) >> 32);
  }
  // A level of the variant that shows at level-0 texel coordinates (s, t) of a surface.
  const TextureLevel& levelAt(int level, uint32_t key, float s, float t) const {
    if (variantCount_ == 1) return views_[static_cast<size_t>(level)];
    return this->level(level, variantAt(key, fastFloor(s) >> views_[0].shiftX, fastFloor(t) >> views_[0].shiftY));
  }
  bool wrap() const { return wrap_; }
  float texelsPerMetre() const { return texelsPerMetre_; }
  // Mean grey level (0..255) of the whole picture (variant 0): a laser's idea of its reflectance.
  float meanGrey() const { return meanGrey_; }

  // The level whose texels span about one pixel, when one pixel spans `texelsPerPixel` level-0
  // texels (rounded in log2, so between 0.7 and 1.4 texels per pixel after the choice).
  int levelFor(float texelsPerPixel) const {
    if (!(texelsPerPixel > 1.41421356f)) return 0;
    // floor(log2(x) + 0.5) = exponent of x * sqrt(2), read from the float's bits (no libm call
    // in the renderer's inner loop).
    const float scaled = texelsPerPixel * 1.41421356f;
    uint32_t bits;
    std::memcpy(&bits, &scaled, sizeof(bits));
    const int l = static_cast<int>((bits >> 23) & 0xffu) - 127;
    return l < levels() ? l : levels() - 1;
  }

 private:
  std::vector<cv::Mat> levels_;       // variant-major: variant v's level l at v * levelCount_ + l
  std::vector<TextureLevel> views_;   // the same order
  int levelCount_ = 0;
  int variantCount_ = 0;
  uint32_t salt_ = 0;
  bool wrap_ = false;
  float texelsPerMetre_ = 1.0f;
  float meanGrey_ = 0.0f;
};

// Bilinear sample of a level at level-0 texel coordinates (s, t) into bgr[3]. Inline: the
// renderer calls it for every pixel. (Across a tile border the second texel comes from the
// same variant, wrapped: variants share their border's structure, so this is within a grey
// level or two of the neighbouring tile's texel.)

inline void sampleBilinear(const TextureLevel& l, float s, float t, uint8_t bgr[3]) {
  const float x = s * l.scaleX - 0.5f;
  const float y = t * l.scaleY - 0.5f;
  int x0 = fastFloor(x);
  int y0 = fastFloor(y);
  // 8-bit fixed-point weights: exact enough for 8-bit images and twice as fast as floats.
  const int wx = static_cast<int>((x - static_cast<float>(x0)) * 256.0f);
  const int wy = static_cast<int>((y - static_cast<float>(y0)) * 256.0f);
  int x1, y1;
  if (l.wrap) {
    x0 &= l.width - 1;
    y0 &= l.height - 1;
    x1 = (x0 + 1) & (l.width - 1);
    y1 = (y0 + 1) & (l.height - 1);
  } else {
    x1 = x0 + 1;
    y1 = y0 + 1;
    x0 = x0 < 0 ? 0 : (x0 >= l.width ? l.width - 1 : x0);
    x1 = x1 < 0 ? 0 : (x1 >= l.width ? l.width - 1 : x1);
    y0 = y0 < 0 ? 0 : (y0 >= l.height ? l.height - 1 : y0);
    y1 = y1 < 0 ? 0 : (y1 >= l.height ? l.height - 1 : y1);
  }
  const uint8_t* c0 = l.data + static_cast<size_t>(x0) * l.step;
  const uint8_t* c1 = l.data + static_cast<size_t>(x1) * l.step;
  const uint8_t* p00 = c0 + y0 * 3;
  const uint8_t* p01 = c1 + y0 * 3;
  const uint8_t* p10 = c0 + y1 * 3;
  const uint8_t* p11 = c1 + y1 * 3;
  for (int c = 0; c < 3; ++c) {
    const int top = p00[c] * (256 - wx) + p01[c] * wx;
    const int bottom = p10[c] * (256 - wx) + p11[c] * wx;
    bgr[c] = static_cast<uint8_t>((top * (256 - wy) + bottom * wy + 32768) >> 16);
  }
}

}  // namespace rtabmap::sim

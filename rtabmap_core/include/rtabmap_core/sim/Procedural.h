#pragma once
// Procedural building blocks for the simulator's textures: periodic value noise (so a material
// tiles without seams), fractal sums of it, cellular patterns, and colour helpers. Pure
// functions of their arguments and a seed: the same inputs give the same texels on any thread.
#include <opencv2/core/matx.hpp>

#include <cstdint>

namespace rtabmap::sim {

// Tile variants: `variant` 0 is the plain periodic pattern. Another variant draws other random
// values on every lattice point except those of row 0 and column 0 (the tile's border), and on
// every cellular cell except the first and last row and column, which keep variant 0's: any
// two variants placed side by side meet without a seam, so a surface can show a different
// variant on each tile (Texture.h) and not repeat from tile to tile.
//
// Smooth value noise in [0, 1] at lattice coordinates (x, y), repeating every periodX lattice
// cells along x and periodY along y (both >= 1).
float valueNoise(float x, float y, int periodX, int periodY, uint32_t seed, uint32_t variant = 0);
// Sum of `octaves` value noises, each twice the frequency (and period) and `gain` times the
// amplitude of the previous, normalised back to [0, 1].
float fbm(float x, float y, int octaves, int periodX, int periodY, uint32_t seed, float gain = 0.5f,
          uint32_t variant = 0);
// Distance from (x, y) to the nearest feature point of a jittered grid (one random point per
// cell, `period` cells per tile), in cell units, and the hash of that point's cell.
float cellular(float x, float y, int period, uint32_t seed, uint32_t* cellHash = nullptr, uint32_t variant = 0);
// The seed a tile variant uses for the random values of a lattice point or cell (wrapped
// indices x, y): variant 0's seed on the tile's border row and column, another one inside.
inline uint32_t variantSeed(int x, int y, uint32_t seed, uint32_t variant) {
  return (variant == 0 || x == 0 || y == 0) ? seed : seed ^ (variant * 0x9e3779b9u + 0x7f4a7c15u);
}

// Colours: hue in degrees [0, 360), saturation and value in [0, 1]; result BGR in [0, 255].
cv::Vec3f hsv(float hueDegrees, float saturation, float value);
cv::Vec3f mixColour(const cv::Vec3f& a, const cv::Vec3f& b, float t);
// Rounds and clamps to 8 bits.
cv::Vec3b toBgr8(const cv::Vec3f& colour);

inline float clamp01(float v) { return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v); }
inline float smoothstep(float e0, float e1, float x) {
  const float t = clamp01((x - e0) / (e1 - e0));
  return t * t * (3.0f - 2.0f * t);
}
// x modulo m into [0, m).
inline float wrapf(float x, float m) {
  float r = x - m * static_cast<float>(static_cast<int>(x / m));
  if (r < 0.0f) r += m;
  if (r >= m) r -= m;
  return r;
}
inline int wrapi(int x, int m) {
  const int r = x % m;
  return r < 0 ? r + m : r;
}

}  // namespace rtabmap::sim

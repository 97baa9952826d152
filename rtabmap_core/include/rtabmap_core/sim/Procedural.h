#pragma once
// Procedural building blocks for the simulator's textures: periodic value noise (so a material
// tiles without seams), fractal sums of it, cellular patterns, and colour helpers. Pure
// functions of their arguments and a seed: the same inputs give the same texels on any thread.
#include <opencv2/core/matx.hpp>

#include <cstdint>

namespace rtabmap::sim {

// Smooth value noise in [0, 1] at lattice coordinates (x, y), repeating every periodX lattice
// cells along x and periodY along y (both >= 1).
float valueNoise(float x, float y, int periodX, int periodY, uint32_t seed);
// Sum of `octaves` value noises, each twice the frequency (and period) and `gain` times the
// amplitude of the previous, normalised back to [0, 1].
float fbm(float x, float y, int octaves, int periodX, int periodY, uint32_t seed, float gain = 0.5f);
// Distance from (x, y) to the nearest feature point of a jittered grid (one random point per
// cell, `period` cells per tile), in cell units, and the hash of that point's cell.
float cellular(float x, float y, int period, uint32_t seed, uint32_t* cellHash = nullptr);

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

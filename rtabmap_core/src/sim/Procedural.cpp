#include "rtabmap_core/sim/Procedural.h"

#include <cmath>

#include "rtabmap_core/sim/Random.h"

namespace rtabmap::sim {

namespace {
inline float lattice(int x, int y, uint32_t seed, uint32_t variant) {
  return hashUnit(hash2D(x, y, variantSeed(x, y, seed, variant)));
}
// Floor without a libm call.
inline int floorInt(float x) {
  const int i = static_cast<int>(x);
  return x < static_cast<float>(i) ? i - 1 : i;
}
}  // namespace

float valueNoise(float x, float y, int px, int py, uint32_t seed, uint32_t variant) {
  const int ix = floorInt(x);
  const int iy = floorInt(y);
  float tx = x - static_cast<float>(ix);
  float ty = y - static_cast<float>(iy);
  // Wrap the cell's corners once (two modulos, not eight): the noise repeats every period.
  const int x0 = wrapi(ix, px);
  const int y0 = wrapi(iy, py);
  const int x1 = x0 + 1 == px ? 0 : x0 + 1;
  const int y1 = y0 + 1 == py ? 0 : y0 + 1;
  // Quintic fade: continuous second derivative, no grid-aligned creases for GFTT to pick up.
  tx = tx * tx * tx * (tx * (tx * 6.0f - 15.0f) + 10.0f);
  ty = ty * ty * ty * (ty * (ty * 6.0f - 15.0f) + 10.0f);
  const float a = lattice(x0, y0, seed, variant);
  const float b = lattice(x1, y0, seed, variant);
  const float c = lattice(x0, y1, seed, variant);
  const float d = lattice(x1, y1, seed, variant);
  return (a + (b - a) * tx) + ((c + (d - c) * tx) - (a + (b - a) * tx)) * ty;
}

float fbm(float x, float y, int octaves, int px, int py, uint32_t seed, float gain, uint32_t variant) {
  float sum = 0.0f;
  float amplitude = 1.0f;
  float norm = 0.0f;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * valueNoise(x, y, px, py, seed + 0x9e37u * static_cast<uint32_t>(o), variant);
    norm += amplitude;
    amplitude *= gain;
    x *= 2.0f;
    y *= 2.0f;
    px *= 2;
    py *= 2;
  }
  return sum / norm;
}

float cellular(float x, float y, int period, uint32_t seed, uint32_t* cellHash, uint32_t variant) {
  const int ix = floorInt(x);
  const int iy = floorInt(y);
  const int wx = wrapi(ix, period);
  const int wy = wrapi(iy, period);
  float best = 1e9f;  // squared distance
  uint32_t bestHash = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    const int hy = wy + dy < 0 ? wy + dy + period : (wy + dy >= period ? wy + dy - period : wy + dy);
    for (int dx = -1; dx <= 1; ++dx) {
      const int hx = wx + dx < 0 ? wx + dx + period : (wx + dx >= period ? wx + dx - period : wx + dx);
      // The cells on either side of the tile's border keep variant 0's points: a point near the
      // border then finds the same neighbours whichever variant the next tile shows.
      const bool border = hx == period - 1 || hy == period - 1;
      const uint32_t h = hash2D(hx, hy, border ? seed : variantSeed(hx, hy, seed, variant));
      const float px = static_cast<float>(ix + dx) + hashUnit(h);
      const float py = static_cast<float>(iy + dy) + hashUnit(h * 0x9e3779b9u + 1u);
      const float d = (px - x) * (px - x) + (py - y) * (py - y);
      if (d < best) {
        best = d;
        bestHash = h;
      }
    }
  }
  if (cellHash) *cellHash = bestHash;
  return std::sqrt(best);
}

cv::Vec3f hsv(float h, float s, float v) {
  h = wrapf(h, 360.0f) / 60.0f;
  const int i = static_cast<int>(h) % 6;
  const float f = h - std::floor(h);
  const float p = v * (1.0f - s);
  const float q = v * (1.0f - s * f);
  const float t = v * (1.0f - s * (1.0f - f));
  float r, g, b;
  switch (i) {
    case 0: r = v; g = t; b = p; break;
    case 1: r = q; g = v; b = p; break;
    case 2: r = p; g = v; b = t; break;
    case 3: r = p; g = q; b = v; break;
    case 4: r = t; g = p; b = v; break;
    default: r = v; g = p; b = q; break;
  }
  return cv::Vec3f(b * 255.0f, g * 255.0f, r * 255.0f);
}

cv::Vec3f mixColour(const cv::Vec3f& a, const cv::Vec3f& b, float t) { return a + (b - a) * t; }

cv::Vec3b toBgr8(const cv::Vec3f& c) {
  cv::Vec3b out;
  for (int i = 0; i < 3; ++i) {
    const float v = c[i] + 0.5f;
    out[i] = static_cast<uint8_t>(v <= 0.0f ? 0 : (v >= 255.0f ? 255 : static_cast<int>(v)));
  }
  return out;
}

}  // namespace rtabmap::sim

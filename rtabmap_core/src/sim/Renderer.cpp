#include "rtabmap_core/sim/Renderer.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rtabmap_core/sim/Random.h"

namespace rtabmap::sim {

namespace {

inline void put(uint8_t* px, const uint8_t texel[3], float gain) {
  const int g = static_cast<int>(gain * 256.0f + 0.5f);  // 8.8 fixed point
  for (int c = 0; c < 3; ++c) {
    const int v = (texel[c] * g + 128) >> 8;
    px[c] = static_cast<uint8_t>(v > 255 ? 255 : v);
  }
}

const uint8_t kGrey[3] = {128, 128, 128};

// One texture column as a wall column sees it: the horizontal texel pair and weight are the
// same on every row (s is constant on a vertical face), so only the vertical position moves,
// in 16.16 fixed point. Equivalent to sampleBilinear(level, s, t0 + i * dt) for row i. With
// tile variants, the column switches variant where it crosses into another tile row.
struct TextureColumn {
  const uint8_t* c0 = nullptr;  // the two stored rows (= picture columns) to blend
  const uint8_t* c1 = nullptr;
  size_t off0 = 0, off1 = 0;    // their byte offsets in a level
  int wx = 0;                   // weight of c1, 0..256
  int height = 0;
  bool wrap = false;
  int64_t y = 0;                // current row coordinate (texels, 16.16, texel centre at 0)
  int64_t dy = 0;
  const Texture* varied = nullptr;  // set when the texture has variants
  int level = 0;
  uint32_t key = 0;
  int tileX = 0;
  int tileY = 0;                // the tile row c0/c1 point into
  int shiftY = 0;

  TextureColumn(const Texture& tex, int levelIndex, uint32_t variantKey, float s, float t0, float dt)
      : level(levelIndex), key(variantKey) {
    const TextureLevel& l = tex.level(levelIndex);
    height = l.height;
    wrap = l.wrap;
    const float x = s * l.scaleX - 0.5f;
    int x0 = fastFloor(x);
    wx = static_cast<int>((x - static_cast<float>(x0)) * 256.0f);
    int x1 = x0 + 1;
    if (wrap) {
      tileX = x0 >> l.shiftX;
      x0 &= l.width - 1;
      x1 &= l.width - 1;
    } else {
      x0 = std::clamp(x0, 0, l.width - 1);
      x1 = std::clamp(x1, 0, l.width - 1);
    }
    off0 = static_cast<size_t>(x0) * l.step;
    off1 = static_cast<size_t>(x1) * l.step;
    c0 = l.data + off0;
    c1 = l.data + off1;
    y = static_cast<int64_t>(std::llround((t0 * l.scaleY - 0.5) * 65536.0));
    dy = static_cast<int64_t>(std::llround(static_cast<double>(dt) * l.scaleY * 65536.0));
    if (tex.variants() > 1) {
      varied = &tex;
      shiftY = l.shiftY;
      selectTileRow(static_cast<int>(y >> 16) >> shiftY);
    }
  }
  void selectTileRow(int ty) {
    tileY = ty;
    const TextureLevel& l = varied->level(level, varied->variantAt(key, tileX, ty));
    c0 = l.data + off0;
    c1 = l.data + off1;
  }
  // The texel at the current row, then one row on.
  inline void next(uint8_t out[3]) {
    const int yi = static_cast<int>(y >> 16);  // arithmetic shift: floor, also below zero
    if (varied && (yi >> shiftY) != tileY) selectTileRow(yi >> shiftY);
    const int wy = static_cast<int>((y >> 8) & 255);
    int y0 = yi, y1 = yi + 1;
    if (wrap) {
      y0 &= height - 1;
      y1 &= height - 1;
    } else {
      y0 = std::clamp(y0, 0, height - 1);
      y1 = std::clamp(y1, 0, height - 1);
    }
    const uint8_t* a = c0 + 3 * y0;
    const uint8_t* b = c1 + 3 * y0;
    const uint8_t* c = c0 + 3 * y1;
    const uint8_t* d = c1 + 3 * y1;
    for (int k = 0; k < 3; ++k) {
      const int top = a[k] * (256 - wx) + b[k] * wx;
      const int bottom = c[k] * (256 - wx) + d[k] * wx;
      out[k] = static_cast<uint8_t>((top * (256 - wy) + bottom * wy + 32768) >> 16);
    }
    y += dy;
  }
};

// The state of one column while it is filled front to back: rows [vTop, vBot) are unfilled.
struct ColumnFill {
  const World& world;
  const CameraIntrinsics& K;
  double camX, camY, camZ;
  Eigen::Vector2d dir;  // floor-plan ray per unit of depth
  double dirNorm;
  float ceiling;
  bool lighting;
  uint8_t* colour;      // this column's H pixels (BGR)
  float* depth;         // this column's H depths
  const float* vignette;
  const double* rowInv;  // 1 / (v - cy) per row
  int vTop = 0;
  int vBot = 0;

  // Floor (material from the region raster) or a furniture top (`top`) at height h < camZ,
  // for depths in [ta, tb).
  void horizontal(double ta, double tb, float h, const SurfaceMaterial* top) {
    const double k = K.fy * (camZ - h);
    if (k <= 0.0) return;
    const int last = ta > 1e-9 ? static_cast<int>(std::floor(std::min(K.cy + k / ta, 1e9))) : vBot - 1;
    const int v0 = std::max(static_cast<int>(std::floor(K.cy + k / tb)) + 1, vTop);
    const int v1 = std::min(last, vBot - 1);
    if (v0 > v1) return;
    const auto& textures = world.textures();
    for (int v = v0; v <= v1; ++v) {
      const double z = k * rowInv[v];
      const double px = camX + z * dir.x();
      const double py = camY + z * dir.y();
      const SurfaceMaterial& m = top ? *top : world.floorAt(px, py);
      uint8_t texel[3];
      if (m.texture >= 0) {
        const Texture& tex = textures[static_cast<size_t>(m.texture)];
        const float tpm = tex.texelsPerMetre();
        // Footprint: across the ray z|d|/fx, along it (foreshortened) z^2/k, in metres.
        const double metres = std::max(z * dirNorm / K.fx, z * z / k);
        const int level = tex.levelFor(static_cast<float>(metres * tpm));
        const float s = static_cast<float>((px + m.offsetS) * tpm);
        const float t = static_cast<float>((m.offsetT - py) * tpm);
        sampleBilinear(tex.levelAt(level, m.variantKey, s, t), s, t, texel);
      } else {
        std::copy(kGrey, kGrey + 3, texel);
      }
      put(colour + 3 * v, texel, (lighting ? m.shade : 1.0f) * vignette[v]);
      depth[v] = static_cast<float>(z);
    }
    if (v1 == vBot - 1) vBot = v0;
  }

  // The ceiling for depths in [ta, tb).
  void ceilingSpan(double ta, double tb) {
    const double k = K.fy * (ceiling - camZ);
    if (k <= 0.0) return;
    const int first = ta > 1e-9 ? static_cast<int>(std::ceil(std::max(K.cy - k / ta, -1e9))) : vTop;
    const int v0 = std::max(first, vTop);
    const int v1 = std::min(static_cast<int>(std::ceil(K.cy - k / tb)) - 1, vBot - 1);
    if (v0 > v1) return;
    const auto& textures = world.textures();
    for (int v = v0; v <= v1; ++v) {
      const double z = -k * rowInv[v];
      const double px = camX + z * dir.x();
      const double py = camY + z * dir.y();
      const SurfaceMaterial& m = world.ceilingAt(px, py);
      uint8_t texel[3];
      if (m.texture >= 0) {
        const Texture& tex = textures[static_cast<size_t>(m.texture)];
        const float tpm = tex.texelsPerMetre();
        const double metres = std::max(z * dirNorm / K.fx, z * z / k);
        const int level = tex.levelFor(static_cast<float>(metres * tpm));
        const float s = static_cast<float>((px + m.offsetS) * tpm);
        const float t = static_cast<float>((m.offsetT - py) * tpm);
        sampleBilinear(tex.levelAt(level, m.variantKey, s, t), s, t, texel);
      } else {
        std::copy(kGrey, kGrey + 3, texel);
      }
      put(colour + 3 * v, texel, (lighting ? m.shade : 1.0f) * vignette[v]);
      depth[v] = static_cast<float>(z);
    }
    if (v0 == vTop) vTop = v1 + 1;
  }

  // A vertical face crossed at depth t, `s` metres along it, from the floor to its top.
  void vertical(const Face& face, double t, double s) {
    const int vs = static_cast<int>(std::ceil(K.cy + K.fy * (camZ - face.height) / t));
    const int ve = static_cast<int>(std::floor(K.cy + K.fy * camZ / t));
    const int v0 = std::max(vs, vTop);
    const int v1 = std::min(ve, vBot - 1);
    if (v0 <= v1) {
      const SurfaceMaterial& m = face.material;
      const auto& textures = world.textures();
      const Texture* tex = m.texture >= 0 ? &textures[static_cast<size_t>(m.texture)] : nullptr;
      // Which decal (if any) covers this column of the face.
      const Decal* decal = nullptr;
      for (int k = 0; k < face.decalCount; ++k) {
        const Decal& d = world.decals()[static_cast<size_t>(face.firstDecal + k)];
        if (s >= d.s0 && s < d.s1) {
          decal = &d;
          break;
        }
      }
      const double metresPerRow = t / K.fy;
      const double incidence = std::max(0.15, std::fabs(dir.dot(face.normal)) / dirNorm);
      const double metresAcross = t * dirNorm / K.fx / incidence;
      const double footprint = std::max(metresPerRow, metresAcross);
      const double h0 = camZ - (v0 - K.cy) * metresPerRow;  // height seen on row v0
      // Rows covered by the decal (heights [h0d, h1d)) are [d0, d1); the rest show the material.
      int d0 = v1 + 1, d1 = v1 + 1;
      if (decal) {
        d0 = std::max(v0, static_cast<int>(std::floor(K.cy + (camZ - decal->h1) / metresPerRow)) + 1);
        d1 = std::min(v1 + 1, static_cast<int>(std::floor(K.cy + (camZ - decal->h0) / metresPerRow)) + 1);
        if (d0 >= d1) d0 = d1 = v1 + 1;
      }
      const float shade = lighting ? m.shade : 1.0f;
      // Light: shade * (0.86 + 0.14 h / ceiling), linear in the row.
      const float gain0 = lighting ? shade * static_cast<float>(0.86 + 0.14 * h0 / ceiling) : 1.0f;
      const float gainStep = lighting ? -shade * static_cast<float>(0.14 * metresPerRow / ceiling) : 0.0f;
      auto run = [&](int from, int to, TextureColumn* column) {
        for (int v = from; v < to; ++v) {
          uint8_t texel[3];
          if (column) column->next(texel);
          else std::copy(kGrey, kGrey + 3, texel);
          put(colour + 3 * v, texel, (gain0 + gainStep * static_cast<float>(v - v0)) * vignette[v]);
          depth[v] = static_cast<float>(t);
        }
      };
      if (tex) {
        const float tpm = tex->texelsPerMetre();
        // Texture row of pixel row v: (offsetT - height(v)) * tpm, linear in v.
        TextureColumn base(*tex, tex->levelFor(static_cast<float>(footprint * tpm)), m.variantKey,
                           static_cast<float>((s + m.offsetS) * tpm), static_cast<float>((m.offsetT - h0) * tpm),
                           static_cast<float>(metresPerRow * tpm));
        run(v0, d0, &base);
        if (d1 <= v1) {
          base.y += base.dy * (d1 - d0);  // skip the rows the decal covers
          run(d1, v1 + 1, &base);
        }
      } else {
        run(v0, d0, nullptr);
        if (d1 <= v1) run(d1, v1 + 1, nullptr);
      }
      if (d0 < d1) {
        const Texture& dt = world.textures()[static_cast<size_t>(decal->texture)];
        const float dtpm = dt.texelsPerMetre();
        const double hd = camZ - (d0 - K.cy) * metresPerRow;
        TextureColumn picture(dt, dt.levelFor(static_cast<float>(footprint * dtpm)), 0u, static_cast<float>((s - decal->s0) * dtpm),
                              static_cast<float>((decal->h1 - hd) * dtpm), static_cast<float>(metresPerRow * dtpm));
        run(d0, d1, &picture);
      }
    }
    if (vs <= vTop && v1 >= vTop) vTop = v1 + 1;
    if (ve >= vBot - 1 && v0 <= vBot - 1) vBot = std::max(v0, vTop);
  }
};

}  // namespace

Renderer::Renderer(const World& world, const CameraIntrinsics& intrinsics, const RenderOptions& options)
    : world_(world), intrinsics_(intrinsics), options_(options) {
  if (intrinsics.width <= 0 || intrinsics.height <= 0 || !(intrinsics.fx > 0) || !(intrinsics.fy > 0)) {
    throw std::invalid_argument("Renderer: invalid intrinsics");
  }
  rowInv_.resize(static_cast<size_t>(intrinsics.height));
  for (int v = 0; v < intrinsics.height; ++v) {
    const double d = v - intrinsics.cy;
    rowInv_[static_cast<size_t>(v)] = std::fabs(d) > 1e-9 ? 1.0 / d : 1e12;
  }
  // Lens falloff: 1 at the centre, 0.72 in the corners (quadratic in the radius).
  vignetteT_ = cv::Mat(intrinsics.width, intrinsics.height, CV_32FC1, cv::Scalar(1.0f));
  if (options.vignetting) {
    const double halfDiagonal2 = 0.25 * (intrinsics.width * intrinsics.width + intrinsics.height * intrinsics.height);
    for (int u = 0; u < intrinsics.width; ++u) {
      float* row = vignetteT_.ptr<float>(u);
      for (int v = 0; v < intrinsics.height; ++v) {
        const double du = u - 0.5 * (intrinsics.width - 1);
        const double dv = v - 0.5 * (intrinsics.height - 1);
        row[v] = static_cast<float>(1.0 - 0.28 * (du * du + dv * dv) / halfDiagonal2);
      }
    }
  }
}

void Renderer::renderColumns(int u0, int u1, const ViewPose& pose, cv::Mat& bgrT, cv::Mat& depthT) const {
  const CameraIntrinsics& K = intrinsics_;
  const Eigen::Vector2d forward(std::cos(pose.yaw), std::sin(pose.yaw));
  const Eigen::Vector2d right(forward.y(), -forward.x());  // z up: the right of the heading
  const float ceiling = static_cast<float>(world_.ceilingHeight());
  const Eigen::Vector2d origin(pose.x, pose.y);
  std::vector<RayHit> hits;
  hits.reserve(64);
  for (int u = u0; u < u1; ++u) {
    const double xn = (u - K.cx) / K.fx;
    ColumnFill c{world_, K, pose.x, pose.y, pose.z, forward + xn * right, std::sqrt(1.0 + xn * xn), ceiling,
                 options_.lighting, bgrT.ptr<uint8_t>(u), depthT.ptr<float>(u), vignetteT_.ptr<float>(u),
                 rowInv_.data()};
    c.vTop = 0;
    c.vBot = K.height;
    const bool stopped = world_.castRay(origin, c.dir, options_.maxDepth, ceiling - 1e-3f, hits);
    double tPrev = 1e-9;
    float surface = 0.0f;               // height of the surface under the ray: floor or a top
    const SurfaceMaterial* top = nullptr;
    int inside = -1;                    // the low solid whose top we are over
    for (const RayHit& hit : hits) {
      if (hit.t > tPrev) {
        if (surface < pose.z) c.horizontal(tPrev, hit.t, surface, top);
        c.ceilingSpan(tPrev, hit.t);
      }
      if (c.vTop >= c.vBot) break;
      const Face& face = world_.faces()[static_cast<size_t>(hit.face)];
      if (hit.entering) {
        c.vertical(face, hit.t, hit.s);
        inside = face.solid;
        surface = face.height;
        top = &world_.solids()[static_cast<size_t>(face.solid)].top;
      } else if (face.solid == inside) {
        inside = -1;
        surface = 0.0f;
        top = nullptr;
      }
      tPrev = std::max(tPrev, hit.t);
    }
    if (!stopped && c.vTop < c.vBot) {
      if (surface < pose.z) c.horizontal(tPrev, options_.maxDepth, surface, top);
      c.ceilingSpan(tPrev, options_.maxDepth);
    }
    for (int v = c.vTop; v < c.vBot; ++v) {  // nothing there (an open world, or beyond maxDepth)
      c.colour[3 * v] = c.colour[3 * v + 1] = c.colour[3 * v + 2] = 0;
      c.depth[v] = 0.0f;
    }
  }
}

void Renderer::render(const ViewPose& pose, cv::Mat& bgr, cv::Mat* depth, uint64_t noiseKey) const {
  const CameraIntrinsics& K = intrinsics_;
  // Columns are rendered as rows of transposed images: each column's pixels are contiguous.
  cv::Mat bgrT(K.width, K.height, CV_8UC3);
  cv::Mat depthT(K.width, K.height, CV_32FC1);
  const int stripe = 16;
  const int stripes = (K.width + stripe - 1) / stripe;
  cv::parallel_for_(cv::Range(0, stripes), [&](const cv::Range& r) {
    renderColumns(r.start * stripe, std::min(K.width, r.end * stripe), pose, bgrT, depthT);
  });
  if (options_.noiseSigma > 0.0) {
    // Per-pixel noise from a hash of (key, pixel): the same for the same key on any thread.
    const float sigma = static_cast<float>(options_.noiseSigma);
    const uint32_t key = static_cast<uint32_t>(mix64(noiseKey));
    for (int u = 0; u < K.width; ++u) {
      uint8_t* col = bgrT.ptr<uint8_t>(u);
      for (int i = 0; i < 3 * K.height; ++i) {
        const uint32_t h = hash2D(u, i, key);
        // Sum of two uniforms, scaled to unit variance: a cheap bell shape.
        const float n = (hashUnit(h) + hashUnit(h * 0x9e3779b9u) - 1.0f) * 2.449f * sigma;
        const int v = static_cast<int>(std::lround(col[i] + n));
        col[i] = static_cast<uint8_t>(std::clamp(v, 0, 255));
      }
    }
  }
  cv::transpose(bgrT, bgr);
  if (depth) cv::transpose(depthT, *depth);
}

}  // namespace rtabmap::sim

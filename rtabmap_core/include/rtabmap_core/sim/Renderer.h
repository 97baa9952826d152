#pragma once
// Ray-casting renderer of the 2.5D world (World.h) for a camera with no roll or pitch.
//
// Because every surface is either vertical (walls, furniture sides) or horizontal (floor,
// ceiling, furniture tops) and the optical axis is horizontal, one ray per image column in the
// floor plan finds everything the column shows: World::castRay returns the face crossings in
// depth order, and each column is filled front to back analytically:
//  - a vertical face at depth z covers the rows whose height camZ - (v - cy) z / fy lies in
//    [0, face height], all at depth z (so a wall column has one depth and one texture column);
//  - a horizontal surface at height h is at depth fy (camZ - h) / (v - cy) on row v (floor and
//    furniture tops below the eye, the ceiling above), between the crossings that bound it.
// Rows already filled by a nearer surface stay: the unfilled rows always form one interval
// [top, bottom), since everything stands on the floor and the ceiling is above everything.
//
// Depth is the distance along the optical axis (what RGB-D cameras report), exact to float
// precision: back-projecting pixel (u, v) with CameraModel::project at that depth gives a
// point on the surface. Pixel centres are at integer coordinates (u, v), as CameraModel uses.
//
// Textures are sampled bilinearly from the mip level matching the pixel footprint (the
// larger of its two extents on the surface), so far surfaces blur instead of aliasing.
// Optional lighting (per-face orientation shade, brighter towards the ceiling lights) and
// vignetting are view-independent, so a stereo pair stays photo-consistent.
#include <opencv2/core/mat.hpp>

#include <cstdint>
#include <vector>

#include "rtabmap_core/sim/World.h"

namespace rtabmap::sim {

struct CameraIntrinsics {
  double fx = 525.0, fy = 525.0, cx = 319.5, cy = 239.5;
  int width = 640, height = 480;
};

// Optical centre in the world (x, y, z) and the heading of the optical axis in the floor plan.
struct ViewPose {
  double x = 0.0, y = 0.0, z = 0.5, yaw = 0.0;
};

struct RenderOptions {
  bool lighting = true;
  bool vignetting = true;
  double noiseSigma = 0.0;  // per-pixel Gaussian noise, grey levels (0: none, the default)
  double maxDepth = 200.0;  // beyond: nothing (black, depth 0)
};

class Renderer {
 public:
  Renderer(const World& world, const CameraIntrinsics& intrinsics, const RenderOptions& options = {});

  // Renders a colour image (CV_8UC3, BGR) and, if `depth` is given, the depth (CV_32FC1,
  // metres along the optical axis; 0 where nothing is seen). `noiseKey` seeds the pixel noise
  // (same key, same noise). Thread-safe: several views may render at once.
  void render(const ViewPose& pose, cv::Mat& bgr, cv::Mat* depth = nullptr, uint64_t noiseKey = 0) const;

  const CameraIntrinsics& intrinsics() const { return intrinsics_; }

 private:
  void renderColumns(int u0, int u1, const ViewPose& pose, cv::Mat& bgrT, cv::Mat& depthT) const;

  const World& world_;
  CameraIntrinsics intrinsics_;
  RenderOptions options_;
  cv::Mat vignetteT_;  // CV_32FC1, W x H (transposed, one row per image column)
  std::vector<double> rowInv_;  // 1 / (v - cy) per image row
};

}  // namespace rtabmap::sim

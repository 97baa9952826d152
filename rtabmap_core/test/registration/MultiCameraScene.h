#pragma once
// Shared scene of the multi-camera tests: a robot carrying two RGB-D cameras that look in
// different directions (camera 0 forward, camera 1 to the left), in a box room whose walls have
// distinct textures and whose floor and ceiling are plain paint (so every feature lies on a
// known wall plane). Frames are rendered by the simulator's ray caster, exact depth, and the two
// cameras' images are put side by side with one CameraModel each, as rtabmap_conversions does
// for an RGBDImages message.
#include <opencv2/core.hpp>

#include <cmath>
#include <memory>
#include <vector>

#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/sim/Materials.h"
#include "rtabmap_core/sim/Renderer.h"
#include "rtabmap_core/sim/World.h"

namespace rtabmap::multicam_test {

constexpr double kRoomW = 6.0;  // east wall at x = kRoomW
constexpr double kRoomD = 5.0;  // north wall at y = kRoomD
constexpr double kRoomH = 2.5;

inline sim::MaterialSpec wallMaterial(sim::MaterialKind kind, uint32_t seed) {
  sim::MaterialSpec m;
  m.kind = kind;
  m.seed = seed;
  m.colour = {150, 160, 170};
  m.accent = {60, 70, 90};
  return m;
}

// The room [0, W] x [0, D]; walls east, north, west, south with these materials.
inline std::unique_ptr<sim::World> room(sim::MaterialKind east, sim::MaterialKind north,
                                        sim::MaterialKind west = sim::MaterialKind::kWoodPanels,
                                        sim::MaterialKind south = sim::MaterialKind::kBlocks) {
  auto world = std::make_unique<sim::World>(kRoomH);
  auto textured = [&](sim::MaterialKind kind, uint32_t seed) {
    sim::SurfaceMaterial m;
    m.texture = world->addTexture(sim::makeMaterialTexture(wallMaterial(kind, seed), 512, 128.0f));
    return m;
  };
  const float h = static_cast<float>(kRoomH);
  const double t = 0.1;
  auto wall = [&](double x0, double y0, double x1, double y1, const sim::SurfaceMaterial& m) {
    world->addSolid({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, h, sim::SolidKind::kWall, {m}, sim::SurfaceMaterial(),
                    "wall");
  };
  wall(kRoomW, -t, kRoomW + t, kRoomD + t, textured(east, 11));
  wall(-t, kRoomD, kRoomW + t, kRoomD + t, textured(north, 12));
  wall(-t, -t, 0.0, kRoomD + t, textured(west, 13));
  wall(-t, -t, kRoomW + t, 0.0, textured(south, 14));
  const sim::SurfaceMaterial plain = textured(sim::MaterialKind::kPaint, 15);
  world->setRegions(cv::Mat::zeros(1, 1, CV_16UC1), -1000.0, -1000.0, 4000.0, {plain}, {plain});
  world->finalize();
  return world;
}

inline sim::CameraIntrinsics intrinsics() {
  sim::CameraIntrinsics k;
  k.width = 320;
  k.height = 240;
  k.fx = k.fy = 200.0;
  k.cx = 159.5;
  k.cy = 119.5;
  return k;
}

// Camera i's yaw on the robot and its base -> optical transform (0.5 m up).
inline double cameraYaw(int i) { return i == 0 ? 0.0 : M_PI / 2.0; }
inline Transform cameraLocal(int i) {
  const double yaw = cameraYaw(i);
  return Transform(0.1 * std::cos(yaw), 0.1 * std::sin(yaw), 0.5, 0.0, 0.0, yaw) * CameraModel::opticalRotation();
}

// A robot pose on the floor.
inline Transform basePose(double x, double y, double yaw) { return Transform(x, y, 0.0, 0.0, 0.0, yaw); }

// The frame seen from `base` by cameras [0, cameras) side by side (the first `cameras` of the rig).
inline SensorData renderFrame(const sim::World& world, const Transform& base, int cameras = 2, int id = 0,
                              double stamp = 0.0) {
  const sim::CameraIntrinsics k = intrinsics();
  sim::RenderOptions options;
  options.vignetting = false;
  const sim::Renderer renderer(world, k, options);
  std::vector<cv::Mat> images, depths;
  std::vector<CameraModel> models;
  for (int i = 0; i < cameras; ++i) {
    const Transform optical = base * cameraLocal(i);
    sim::ViewPose view;
    view.x = optical.x();
    view.y = optical.y();
    view.z = optical.z();
    view.yaw = base.theta() + cameraYaw(i);
    cv::Mat bgr, depth;
    renderer.render(view, bgr, &depth);
    images.push_back(bgr);
    depths.push_back(depth);
    CameraModel m(k.fx, k.fy, k.cx, k.cy, cameraLocal(i));
    m.setImageSize(cv::Size(k.width, k.height));
    models.push_back(m);
  }
  cv::Mat image, depth;
  cv::hconcat(images, image);
  cv::hconcat(depths, depth);
  SensorData data(image, depth, models, id, stamp);
  return data;
}

}  // namespace rtabmap::multicam_test

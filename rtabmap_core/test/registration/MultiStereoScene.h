#pragma once
// Shared scene of the several-stereo-cameras tests: a robot carrying two rectified stereo
// cameras that look in different directions (camera 0 forward, camera 1 to the left), in the
// SyntheticRoom (a box whose six faces are textured, so every feature lies on a known plane).
// The cameras' left images are put side by side, their right images side by side the same way,
// one StereoCameraModel each, as rtabmap_conversions does for an RGBDImages of stereo entries.
#include <opencv2/core.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

#include "odometry/SyntheticRoom.h"
#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/StereoCameraModel.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap::multistereo_test {

constexpr double kBaseline = 0.12;

// Camera i's yaw on the robot and its base -> left optical transform (1 m up).
inline double cameraYaw(int i) { return i == 0 ? 0.0 : M_PI / 2.0; }
inline Transform cameraLocal(int i) {
  const double yaw = cameraYaw(i);
  return Transform(0.1 * std::cos(yaw), 0.1 * std::sin(yaw), 1.0, 0.0, 0.0, yaw) * CameraModel::opticalRotation();
}

inline StereoCameraModel cameraModel(int i) {
  StereoCameraModel m = test::SyntheticRoom::stereoCamera(320, 240, kBaseline);
  m.setLocalTransform(cameraLocal(i));
  return m;
}

// A robot pose on the floor of the room (centred on the origin).
inline Transform basePose(double x, double y, double yaw) { return Transform(x, y, 0.0, 0.0, 0.0, yaw); }

// The frame seen from `base` by stereo cameras [0, cameras) side by side.
inline SensorData renderStereoFrame(const test::SyntheticRoom& room, const Transform& base, int cameras = 2,
                                    int id = 0, double stamp = 0.0) {
  std::vector<cv::Mat> lefts, rights;
  std::vector<StereoCameraModel> models;
  for (int i = 0; i < cameras; ++i) {
    const StereoCameraModel m = cameraModel(i);
    const Transform leftPose = base * m.localTransform();
    cv::Mat left, right;
    room.render(leftPose, m.left(), left, nullptr);
    room.render(leftPose * Transform(m.baseline(), 0, 0, 0, 0, 0), m.left(), right, nullptr);
    lefts.push_back(left);
    rights.push_back(right);
    models.push_back(m);
  }
  cv::Mat left, right;
  cv::hconcat(lefts, left);
  cv::hconcat(rights, right);
  SensorData data(left, right, models, id, stamp);
  data.setGroundTruth(base);
  return data;
}

// Distance of a world point to the room's surface (its six faces), inside or outside the room.
inline double distanceToRoom(const test::SyntheticRoom& room, const Eigen::Vector3d& p) {
  const double h = room.halfSize();
  const Eigen::Vector3d lo(-h, -h, 0.0), hi(h, h, room.height());
  const Eigen::Vector3d inside = p.cwiseMax(lo).cwiseMin(hi);
  if ((inside - p).norm() > 0.0) return (inside - p).norm();
  return std::min({h - std::abs(p.x()), h - std::abs(p.y()), p.z(), room.height() - p.z()});
}

// How far from the room's surface a stereo point at this depth (m, along the optical axis) may
// be. The error grows with the square of the depth: at 3.3 m this rig (fx 262.5, baseline 12 cm)
// measures disparities under 10 px, and its sparse matches come out up to 0.3 px short (the same
// in the single-camera path, see MultiStereoFeatures.OneCameraAloneIsTheSingleStereoPath): 12 cm
// of depth. A wrong model or local transform moves points by metres.
inline double depthTolerance(double depth) { return 0.01 + 0.04 * depth * depth / 3.0; }

}  // namespace rtabmap::multistereo_test

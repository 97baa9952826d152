#pragma once
// Synthetic worlds for the ICP and lidar odometry tests: 2D worlds of wall segments ray-cast by
// a planar lidar, and 3D worlds of axis-aligned boxes ray-cast by a spinning lidar. Exact
// geometry (optional Gaussian range noise) so a test knows the true transform.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap::test {

struct Segment {
  double x1, y1, x2, y2;
};
using World2D = std::vector<Segment>;

// Closed polygon (x0 y0 x1 y1 ...) as segments.
inline void addPolygon(World2D& world, const std::vector<double>& xy) {
  const size_t n = xy.size() / 2;
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    world.push_back({xy[2 * i], xy[2 * i + 1], xy[2 * j], xy[2 * j + 1]});
  }
}

// An L-shaped building floor: a 20 x 12 m outer shell, inner walls, pillars and a few crates,
// so every place sees surfaces facing several directions.
inline World2D officeWorld() {
  World2D w;
  addPolygon(w, {0, 0, 20, 0, 20, 12, 0, 12});
  w.push_back({6, 0, 6, 5});
  w.push_back({6, 7, 6, 12});
  w.push_back({12, 4, 20, 4});
  w.push_back({14, 8, 14, 12});
  addPolygon(w, {3, 3, 3.4, 3, 3.4, 3.4, 3, 3.4});
  addPolygon(w, {9, 8, 9.5, 8, 9.5, 8.5, 9, 8.5});
  addPolygon(w, {16, 6, 17, 6.3, 16.7, 7.2, 15.8, 6.9});
  addPolygon(w, {10, 2, 11, 2, 11, 2.6, 10, 2.6});
  return w;
}

// A straight corridor along x: two parallel walls 2 m apart, far longer than the lidar's range.
inline World2D corridorWorld() { return {{-100, -1, 100, -1}, {-100, 1, 100, 1}}; }

struct Lidar2D {
  int beams = 360;
  double angleMin = -M_PI;
  double angleMax = M_PI - 2 * M_PI / 360;
  double rangeMin = 0.1;
  double rangeMax = 30.0;
  double noise = 0.0;  // range standard deviation (m)
};

// Planar scan seen from `pose` (x, y, yaw of the sensor in the world).
inline LaserScan castScan2D(const World2D& world, const Transform& pose, const Lidar2D& lidar,
                            std::mt19937* rng = nullptr) {
  std::vector<float> ranges(static_cast<size_t>(lidar.beams));
  const double increment = (lidar.angleMax - lidar.angleMin) / std::max(1, lidar.beams - 1);
  std::normal_distribution<double> noise(0.0, lidar.noise);
  for (int b = 0; b < lidar.beams; ++b) {
    const double a = pose.theta() + lidar.angleMin + b * increment;
    const double dx = std::cos(a), dy = std::sin(a);
    double best = std::numeric_limits<double>::infinity();
    for (const Segment& s : world) {
      // Solve pose + r d = s1 + u (s2 - s1), r > 0, u in [0, 1].
      const double ex = s.x2 - s.x1, ey = s.y2 - s.y1;
      const double den = dx * ey - dy * ex;
      if (std::abs(den) < 1e-12) continue;
      const double wx = s.x1 - pose.x(), wy = s.y1 - pose.y();
      const double r = (wx * ey - wy * ex) / den;
      const double u = (wx * dy - wy * dx) / den;
      if (r > 0 && u >= 0 && u <= 1 && r < best) best = r;
    }
    if (std::isfinite(best) && lidar.noise > 0 && rng) best += noise(*rng);
    ranges[static_cast<size_t>(b)] = static_cast<float>(best);
  }
  return LaserScan::fromRanges(ranges, lidar.angleMin, increment, lidar.rangeMin, lidar.rangeMax);
}

struct Box {
  Eigen::Vector3d min, max;
};
struct World3D {
  Box room;                // the rays start inside it and exit through its walls
  std::vector<Box> solids; // obstacles inside
};

// A 30 x 20 x 6 m hall with pillars, crates and a ramp-like step, so all six degrees of freedom
// are observable.
inline World3D hallWorld() {
  World3D w;
  w.room = {{-15, -10, -1.5}, {15, 10, 4.5}};
  w.solids.push_back({{3, 2, -1.5}, {3.6, 2.6, 4.5}});
  w.solids.push_back({{-4, -3, -1.5}, {-3.4, -2.4, 4.5}});
  w.solids.push_back({{6, -5, -1.5}, {8, -4, -0.5}});
  w.solids.push_back({{-8, 4, -1.5}, {-6, 7, 0.5}});
  w.solids.push_back({{-2, 6, -1.5}, {2, 7, 1.5}});
  w.solids.push_back({{9, 3, -1.5}, {11, 9, -1.0}});
  return w;
}

// Ray / box: entry and exit distances (tmin > tmax when missed).
inline void rayBox(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Box& b, double* tmin, double* tmax) {
  double t0 = -std::numeric_limits<double>::infinity(), t1 = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-12) {
      if (o[i] < b.min[i] || o[i] > b.max[i]) {
        *tmin = 1;
        *tmax = 0;
        return;
      }
      continue;
    }
    double a = (b.min[i] - o[i]) / d[i], c = (b.max[i] - o[i]) / d[i];
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
  }
  *tmin = t0;
  *tmax = t1;
}

// Spinning lidar at `pose` (6 DoF): `rings` elevations in [-15, 15] degrees, `azimuths` per
// ring. XYZ points in the sensor frame.
inline LaserScan castScan3D(const World3D& world, const Transform& pose, int rings = 16, int azimuths = 360,
                            double rangeMax = 40.0) {
  std::vector<float> xyz;
  const Eigen::Matrix3d R = pose.rotationMatrix();
  const Eigen::Vector3d o = pose.translation();
  for (int r = 0; r < rings; ++r) {
    const double elevation = (-15.0 + 30.0 * r / std::max(1, rings - 1)) * M_PI / 180.0;
    for (int a = 0; a < azimuths; ++a) {
      const double azimuth = 2 * M_PI * a / azimuths;
      const Eigen::Vector3d local(std::cos(elevation) * std::cos(azimuth),
                                  std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      const Eigen::Vector3d d = R * local;
      double t0, t1;
      rayBox(o, d, world.room, &t0, &t1);
      double best = t1;  // exit of the room
      for (const Box& b : world.solids) {
        rayBox(o, d, b, &t0, &t1);
        if (t0 <= t1 && t0 > 0 && t0 < best) best = t0;
      }
      if (!(best > 0.2 && best < rangeMax)) continue;
      const Eigen::Vector3d p = local * best;
      xyz.push_back(static_cast<float>(p.x()));
      xyz.push_back(static_cast<float>(p.y()));
      xyz.push_back(static_cast<float>(p.z()));
    }
  }
  cv::Mat data(1, static_cast<int>(xyz.size() / 3), CV_32FC3);
  if (!xyz.empty()) std::memcpy(data.ptr<float>(0), xyz.data(), xyz.size() * sizeof(float));
  return LaserScan(data, rings * azimuths, 0.2, rangeMax, LaserScan::kXYZ);
}

// Poses every `step` metres along straight legs through the waypoints (x, y), heading along
// each leg; at a corner the robot turns in place by at most `turnStep` radians per pose.
inline std::vector<Transform> pathThrough(const std::vector<std::pair<double, double>>& waypoints, double step,
                                          double turnStep = 0.1) {
  std::vector<Transform> poses;
  double heading = std::atan2(waypoints[1].second - waypoints[0].second, waypoints[1].first - waypoints[0].first);
  for (size_t i = 0; i + 1 < waypoints.size(); ++i) {
    const auto [x0, y0] = waypoints[i];
    const auto [x1, y1] = waypoints[i + 1];
    const double target = std::atan2(y1 - y0, x1 - x0);
    double turn = std::remainder(target - heading, 2 * M_PI);
    while (std::abs(turn) > 1e-9) {
      const double d = std::max(-turnStep, std::min(turnStep, turn));
      heading += d;
      turn -= d;
      poses.emplace_back(x0, y0, heading);
    }
    const double length = std::hypot(x1 - x0, y1 - y0);
    const int steps = std::max(1, static_cast<int>(std::round(length / step)));
    for (int k = (i == 0 ? 0 : 1); k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      poses.emplace_back(x0 + t * (x1 - x0), y0 + t * (y1 - y0), heading);
    }
  }
  return poses;
}

// Wheel odometry from true poses: each increment scaled by (1 + scaleError) in translation and
// given an extra yaw of yawPerMetre per metre travelled, so it drifts as real wheels do.
inline std::vector<Transform> wheelOdometry(const std::vector<Transform>& truth, double scaleError,
                                            double yawPerMetre) {
  std::vector<Transform> odom{truth.front()};
  for (size_t i = 1; i < truth.size(); ++i) {
    const Transform d = truth[i - 1].inverse() * truth[i];
    const double dist = d.getNorm2D();
    const Transform noisy(d.x() * (1 + scaleError), d.y() * (1 + scaleError), d.theta() + yawPerMetre * dist);
    odom.push_back(odom.back() * noisy);
  }
  return odom;
}

// Errors of an estimate against the truth: translation (m) and rotation (rad).
inline double translationError(const Transform& estimate, const Transform& truth) {
  return (truth.inverse() * estimate).getNorm();
}
inline double rotationError(const Transform& estimate, const Transform& truth) {
  return (truth.inverse() * estimate).getAngle();
}

}  // namespace rtabmap::test

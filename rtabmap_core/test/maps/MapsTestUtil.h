#pragma once
// Synthetic scenes for the maps tests: a planar lidar in a polygonal world of boxes, and a depth
// camera looking at a floor with boxes (a box, a table with its top and legs), rendered by exact
// ray casting so that the expected cells are known.
#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap::test {

struct Box {
  Eigen::Vector3d lo, hi;
};

// Distance along a unit direction from o to the first box face, or +inf.
inline double rayBox(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Box& b) {
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-12) {
      if (o[a] < b.lo[a] || o[a] > b.hi[a]) return std::numeric_limits<double>::infinity();
      continue;
    }
    double ta = (b.lo[a] - o[a]) / d[a], tb = (b.hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return std::numeric_limits<double>::infinity();
  }
  return t0 > 1e-9 ? t0 : std::numeric_limits<double>::infinity();
}

// A closed rectangular room [x0, x1] x [y0, y1] with walls 0.2 m thick, plus inner boxes.
struct World2D {
  std::vector<Box> boxes;
  static World2D room(double x0, double y0, double x1, double y1) {
    World2D w;
    const double t = 0.2;
    w.boxes.push_back({{x0 - t, y0 - t, -1}, {x1 + t, y0, 1}});
    w.boxes.push_back({{x0 - t, y1, -1}, {x1 + t, y1 + t, 1}});
    w.boxes.push_back({{x0 - t, y0, -1}, {x0, y1, 1}});
    w.boxes.push_back({{x1, y0, -1}, {x1 + t, y1, 1}});
    return w;
  }
  double cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
    double best = std::numeric_limits<double>::infinity();
    for (const Box& b : boxes) best = std::min(best, rayBox(o, d, b));
    return best;
  }
};

// A planar scan (beams over fov, sensor at `pose` in the world, z = 0): ranges beyond rangeMax
// are no-returns (+inf), as a driver reports them.
inline std::vector<float> simulateRanges(const World2D& world, const Transform& pose, int beams,
                                         double fov, double rangeMax) {
  std::vector<float> ranges(beams);
  const Eigen::Vector3d o = pose.translation();
  for (int i = 0; i < beams; ++i) {
    const double a = -fov / 2 + fov * i / (beams - 1);
    const Eigen::Vector3d d = pose.rotationMatrix() * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
    const double r = world.cast(o, d);
    ranges[i] = r <= rangeMax ? static_cast<float>(r) : std::numeric_limits<float>::infinity();
  }
  return ranges;
}

inline LaserScan simulateScan(const World2D& world, const Transform& pose, int beams = 181,
                              double fov = M_PI, double rangeMax = 10.0) {
  return LaserScan::fromRanges(simulateRanges(world, pose, beams, fov, rangeMax), -fov / 2,
                               fov / (beams - 1), 0.0, rangeMax);
}

// A depth camera (width x height, focal f) at height h on the robot, pitched down by `pitch`,
// looking at a floor (z = 0) with boxes. Depth in metres (CV_32FC1), 0 where nothing is hit
// within maxDepth. The colour image paints the floor grey and boxes red.
struct DepthScene {
  std::vector<Box> boxes;
  double maxDepth = 8.0;

  static DepthScene floorBoxTable() {
    DepthScene s;
    // Faces off the 5 cm lattice, so that each face falls in one voxel whatever the rounding.
    s.boxes.push_back({{2.02, -0.82, 0.0}, {2.42, -0.42, 0.52}});  // a box
    // A table: top at 0.70-0.74 m and four legs.
    s.boxes.push_back({{1.82, 0.32, 0.70}, {2.62, 1.12, 0.74}});
    for (double lx : {1.84, 2.56}) {
      for (double ly : {0.34, 1.06}) s.boxes.push_back({{lx, ly, 0.0}, {lx + 0.04, ly + 0.04, 0.70}});
    }
    return s;
  }

  SensorData render(int width, int height, double f, double camHeight, double pitch,
                    const Transform& robotPose = Transform::Identity(), int id = 1) const {
    const Transform local = Transform(0, 0, camHeight, 0, pitch, 0) * CameraModel::opticalRotation();
    const CameraModel model(f, f, width / 2.0, height / 2.0, local, 0.0, cv::Size(width, height));
    cv::Mat depth(height, width, CV_32FC1, cv::Scalar(0));
    cv::Mat rgb(height, width, CV_8UC3, cv::Scalar(128, 128, 128));
    const Transform camInWorld = robotPose * local;
    const Eigen::Matrix3d R = camInWorld.rotationMatrix();
    const Eigen::Vector3d o = camInWorld.translation();
    for (int v = 0; v < height; ++v) {
      for (int u = 0; u < width; ++u) {
        const Eigen::Vector3d dOpt((u - width / 2.0) / f, (v - height / 2.0) / f, 1.0);
        const Eigen::Vector3d d = R * dOpt;  // not unit: t is the optical depth
        double t = d.z() < -1e-9 ? -o.z() / d.z() : std::numeric_limits<double>::infinity();
        bool box = false;
        const double n = d.norm();
        for (const Box& b : boxes) {
          const double tb = rayBox(o, d / n, b) / n;
          if (tb < t) {
            t = tb;
            box = true;
          }
        }
        if (t <= maxDepth) {
          depth.at<float>(v, u) = static_cast<float>(t);
          if (box) rgb.at<cv::Vec3b>(v, u) = cv::Vec3b(0, 0, 255);
        }
      }
    }
    SensorData data(rgb, depth, model, id);
    return data;
  }
};

// Count of cells (points of a CV_32FC2/3/4 matrix) inside an axis-aligned xy rectangle, and
// optionally a z band.
inline int countIn(const cv::Mat& cells, double x0, double y0, double x1, double y1,
                   double z0 = -1e9, double z1 = 1e9) {
  if (cells.empty()) return 0;
  int n = 0;
  const int ch = cells.channels();
  const float* p = cells.ptr<float>();
  for (size_t i = 0; i < cells.total(); ++i, p += ch) {
    const double z = ch >= 3 ? p[2] : 0.0;
    n += p[0] >= x0 && p[0] <= x1 && p[1] >= y0 && p[1] <= y1 && z >= z0 && z <= z1;
  }
  return n;
}

}  // namespace rtabmap::test

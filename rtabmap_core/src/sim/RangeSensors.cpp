#include "rtabmap_core/sim/RangeSensors.h"

#include <cmath>
#include <limits>

#include "rtabmap_core/sim/Random.h"

namespace rtabmap::sim {

namespace {

// Brightness of a face where a beam hits it, from a coarse mip level of its material (a laser
// spot is centimetres wide), times the material's reflectivity: 0..1000.
float intensityAt(const World& world, const Face& face, double s, double h) {
  const SurfaceMaterial& m = face.material;
  float brightness = 0.5f;
  if (m.texture >= 0) {
    const Texture& tex = world.textures()[static_cast<size_t>(m.texture)];
    const float tpm = tex.texelsPerMetre();
    uint8_t bgr[3];
    const float ts = static_cast<float>((s + m.offsetS) * tpm);
    const float tt = static_cast<float>((m.offsetT - h) * tpm);
    sampleBilinear(tex.levelAt(std::min(2, tex.levels() - 1), m.variantKey, ts, tt), ts, tt, bgr);
    brightness = (0.114f * bgr[0] + 0.587f * bgr[1] + 0.299f * bgr[2]) / 255.0f;
  }
  return 1000.0f * m.reflectivity * (0.4f + 0.6f * brightness);
}

// Laser pose in the world: the base pose composed with the sensor's planar mount.
Pose2 mountPose(const Pose2& base, const Transform& mount) {
  return base * Pose2{mount.x(), mount.y(), mount.yaw()};
}

}  // namespace

LaserReading simulateLaser(const World& world, const LaserSpec& spec, const Pose2& base, uint64_t noiseKey) {
  LaserReading out;
  out.ranges.resize(static_cast<size_t>(spec.beams));
  out.intensities.resize(static_cast<size_t>(spec.beams));
  const Pose2 laser = mountPose(base, spec.baseToLaser);
  const double height = spec.baseToLaser.z();
  const Eigen::Vector2d origin(laser.x, laser.y);
  Rng noise(noiseKey, "laser/" + spec.name);
  std::vector<RayHit> hits;
  const float inf = std::numeric_limits<float>::infinity();
  for (int i = 0; i < spec.beams; ++i) {
    const double a = laser.yaw + spec.angleMin + i * spec.angleIncrement;
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    // The beam is blocked by the first solid taller than the scan plane.
    const bool hit = world.castRay(origin, dir, spec.rangeMax + 1.0, static_cast<float>(height + 1e-4), hits);
    float range = inf;
    float intensity = 0.0f;
    if (hit) {
      const RayHit& h = hits.back();
      double r = h.t;
      if (spec.noiseSigma > 0.0) r += spec.noiseSigma * noise.normal();
      if (r > spec.rangeMax) {
        range = inf;
      } else if (r < spec.rangeMin) {
        range = -inf;
      } else {
        range = static_cast<float>(r);
        intensity = intensityAt(world, world.faces()[static_cast<size_t>(h.face)], h.s, height);
      }
    }
    out.ranges[static_cast<size_t>(i)] = range;
    out.intensities[static_cast<size_t>(i)] = intensity;
  }
  return out;
}

cv::Mat simulateLidar(const World& world, const LidarSpec& spec, const Pose2& base, uint64_t noiseKey) {
  const Pose2 lidar = mountPose(base, spec.baseToLidar);
  const double hL = spec.baseToLidar.z();
  const double ceiling = world.ceilingHeight();
  const Eigen::Vector2d origin(lidar.x, lidar.y);
  std::vector<double> tanE(static_cast<size_t>(spec.rings)), cosE(static_cast<size_t>(spec.rings));
  for (int r = 0; r < spec.rings; ++r) {
    const double e = spec.rings > 1 ? spec.elevationMin + r * (spec.elevationMax - spec.elevationMin) / (spec.rings - 1)
                                    : spec.elevationMin;
    tanE[static_cast<size_t>(r)] = std::tan(e);
    cosE[static_cast<size_t>(r)] = std::cos(e);
  }
  Rng noise(noiseKey, "lidar/" + spec.name);
  cv::Mat points(1, spec.rings * spec.azimuthSteps, CV_32FC4);
  int n = 0;
  std::vector<RayHit> hits;
  for (int j = 0; j < spec.azimuthSteps; ++j) {
    const double azimuth = 2.0 * M_PI * j / spec.azimuthSteps;  // in the lidar frame
    const double a = lidar.yaw + azimuth;
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    const bool stopped = world.castRay(origin, dir, spec.rangeMax, static_cast<float>(ceiling - 1e-3), hits);
    for (int r = 0; r < spec.rings; ++r) {
      const double te = tanE[static_cast<size_t>(r)];
      // Walk the crossings: between two, the beam may meet the surface below (floor or a
      // furniture top it is over) or the ceiling; at an entering face, the face itself if the
      // beam's height there is within it.
      double tPrev = 0.0;
      double surface = 0.0;
      int inside = -1;
      double tHit = -1.0;
      float intensity = 0.0f;
      auto horizontal = [&](double tEnd) {
        if (te < 0.0) {
          const double t = (hL - surface) / -te;
          if (t >= tPrev && t < tEnd) {
            tHit = t;
            intensity = 1000.0f * 0.5f;
            return true;
          }
        } else if (te > 0.0) {
          const double t = (ceiling - hL) / te;
          if (t >= tPrev && t < tEnd) {
            tHit = t;
            intensity = 1000.0f * 0.6f;
            return true;
          }
        }
        return false;
      };
      bool done = false;
      for (const RayHit& h : hits) {
        if (horizontal(h.t)) {
          done = true;
          break;
        }
        const Face& face = world.faces()[static_cast<size_t>(h.face)];
        if (h.entering) {
          const double z = hL + h.t * te;
          if (z >= 0.0 && z <= face.height) {
            tHit = h.t;
            intensity = intensityAt(world, face, h.s, z);
            done = true;
            break;
          }
          inside = face.solid;
          surface = face.height;
        } else if (face.solid == inside) {
          inside = -1;
          surface = 0.0;
        }
        tPrev = h.t;
      }
      if (!done && !stopped) horizontal(spec.rangeMax);
      if (tHit < 0.0) continue;
      double range = tHit / cosE[static_cast<size_t>(r)];
      if (spec.noiseSigma > 0.0) range += spec.noiseSigma * noise.normal();
      if (range < spec.rangeMin || range > spec.rangeMax) continue;
      const double horizontalRange = range * cosE[static_cast<size_t>(r)];
      cv::Vec4f& p = points.at<cv::Vec4f>(0, n++);
      p[0] = static_cast<float>(horizontalRange * std::cos(azimuth));
      p[1] = static_cast<float>(horizontalRange * std::sin(azimuth));
      p[2] = static_cast<float>(horizontalRange * te);
      p[3] = intensity;
    }
  }
  return n > 0 ? cv::Mat(points.colRange(0, n)).clone() : cv::Mat();
}

}  // namespace rtabmap::sim

#pragma once
// Range sensors ray-cast in the 2.5D world: planar lasers (URG-04LX, UTM-30LX) and a 16-beam
// spinning lidar. Ranges are exact unless the spec asks for noise (deterministic per key).
// The scan is taken at one instant (no motion distortion: as if de-skewed).
#include <opencv2/core/mat.hpp>

#include <cstdint>
#include <vector>

#include "rtabmap_core/sim/Pose2.h"
#include "rtabmap_core/sim/SensorRig.h"
#include "rtabmap_core/sim/World.h"

namespace rtabmap::sim {

// One planar scan as sensor_msgs/LaserScan carries it: a range per beam (metres; +inf = no
// return within rangeMax, -inf = closer than rangeMin, REP-117) and an intensity per beam
// (arbitrary units, 0..1000: the surface's reflectivity times its brightness).
struct LaserReading {
  std::vector<float> ranges;
  std::vector<float> intensities;
};

LaserReading simulateLaser(const World& world, const LaserSpec& spec, const Pose2& base, uint64_t noiseKey = 0);

// A lidar sweep: 1 x N CV_32FC4 (x, y, z, intensity) in the lidar frame, azimuth-major (all
// rings of the first azimuth, then the next), only the beams that returned.
cv::Mat simulateLidar(const World& world, const LidarSpec& spec, const Pose2& base, uint64_t noiseKey = 0);

}  // namespace rtabmap::sim

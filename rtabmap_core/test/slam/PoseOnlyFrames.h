#pragma once
// Pose-only input for Rtabmap tests (no images, no scan: nothing can localise or close a loop,
// so the graph is exactly what odometry and the start pose make it).
#include <Eigen/Core>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap::test {

using Cov = Eigen::Matrix<double, 6, 6>;

inline Cov smallCov() { return Cov::Identity() * 1e-4; }
// A node of the graph without appearance.
inline SensorData frame(int id, double stamp) { return SensorData(LaserScan(), id, stamp); }
inline Transform along(double x, double yaw = 0.0) { return Transform(x, 0, 0, 0, 0, yaw); }
// One node per frame (no Rtabmap/DetectionRate throttling).
inline ParametersMap everyFrame() { return {{"Rtabmap/DetectionRate", "0"}}; }

}  // namespace rtabmap::test

#pragma once
// The log-odds occupancy model shared by the 2D grid and the OctoMap. Internal.
#include <cmath>
#include <sstream>

namespace rtabmap {

// Checks GridGlobal/ProbHit, ProbMiss, ProbClampingMin|Max, OccupancyThr; writes the reason.
bool validSensorModel(float hit, float miss, float clampMin, float clampMax, float thr,
                      std::ostringstream& reason);

namespace maps_detail {
inline float logit(float p) { return std::log(p / (1.0f - p)); }
}  // namespace maps_detail

}  // namespace rtabmap

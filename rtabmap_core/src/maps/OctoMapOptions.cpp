#include <cmath>
#include <sstream>

#include "SensorModel.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/OctoMap.h"

namespace rtabmap {

OctoMapOptions OctoMapOptions::fromParameters(const ParametersMap& p) {
  OctoMapOptions o;
  o.cellSize = Parameters::getFloat(p, Parameters::kGridCellSize());
  o.treeDepth = Parameters::getInt(p, Parameters::kGridGlobalOctoMapTreeDepth());
  o.probHit = Parameters::getFloat(p, Parameters::kGridGlobalProbHit());
  o.probMiss = Parameters::getFloat(p, Parameters::kGridGlobalProbMiss());
  o.probClampingMin = Parameters::getFloat(p, Parameters::kGridGlobalProbClampingMin());
  o.probClampingMax = Parameters::getFloat(p, Parameters::kGridGlobalProbClampingMax());
  o.occupancyThr = Parameters::getFloat(p, Parameters::kGridGlobalOccupancyThr());
  o.rayTracing = Parameters::getBool(p, Parameters::kGridRayTracing());
  o.rangeMax = Parameters::getFloat(p, Parameters::kGridRangeMax());
  o.updateError = Parameters::getFloat(p, Parameters::kGridGlobalUpdateError());
  o.floodFillDepth = Parameters::getInt(p, Parameters::kGridGlobalFloodFillDepth());
  return o;
}

bool OctoMapOptions::IsValid(std::string* why) const {
  std::ostringstream r;
  if (!(std::isfinite(cellSize) && cellSize > 0.0f)) {
    r << "Grid/CellSize must be a finite number > 0 (got " << cellSize << ")";
  } else if (treeDepth < 1 || treeDepth > 16) {
    r << "GridGlobal/OctoMapTreeDepth must be between 1 and 16 (got " << treeDepth << ")";
  } else if (validSensorModel(probHit, probMiss, probClampingMin, probClampingMax, occupancyThr, r)) {
    if (!(std::isfinite(rangeMax) && rangeMax >= 0.0f)) {
      r << "Grid/RangeMax must be >= 0 (got " << rangeMax << ")";
    } else if (!(std::isfinite(updateError) && updateError >= 0.0f)) {
      r << "GridGlobal/UpdateError must be >= 0 (got " << updateError << ")";
    } else if (floodFillDepth < 0 || floodFillDepth > 16) {
      r << "GridGlobal/FloodFillDepth must be between 0 and 16 (got " << floodFillDepth << ")";
    }
  }
  const std::string text = r.str();
  if (why) *why = text;
  return text.empty();
}

void OctoMapOptions::validate() const {
  std::string why;
  if (!IsValid(&why)) throw ParameterError("invalid OctoMap options: " + why);
}

}  // namespace rtabmap

#include <cmath>
#include <sstream>

#include "rtabmap_core/common/Error.h"
#include "SensorModel.h"
#include "rtabmap_core/maps/OccupancyGrid.h"

namespace rtabmap {

GlobalGridOptions GlobalGridOptions::fromParameters(const ParametersMap& p) {
  GlobalGridOptions o;
  o.cellSize = Parameters::getFloat(p, Parameters::kGridCellSize());
  o.minSize = Parameters::getFloat(p, Parameters::kGridGlobalMinSize());
  o.probHit = Parameters::getFloat(p, Parameters::kGridGlobalProbHit());
  o.probMiss = Parameters::getFloat(p, Parameters::kGridGlobalProbMiss());
  o.probClampingMin = Parameters::getFloat(p, Parameters::kGridGlobalProbClampingMin());
  o.probClampingMax = Parameters::getFloat(p, Parameters::kGridGlobalProbClampingMax());
  o.occupancyThr = Parameters::getFloat(p, Parameters::kGridGlobalOccupancyThr());
  o.fullUpdate = Parameters::getBool(p, Parameters::kGridGlobalFullUpdate());
  o.updateError = Parameters::getFloat(p, Parameters::kGridGlobalUpdateError());
  o.reassemblyInterval = Parameters::getInt(p, Parameters::kGridGlobalReassemblyInterval());
  o.footprintRadius = Parameters::getFloat(p, Parameters::kGridGlobalFootprintRadius());
  o.eroded = Parameters::getBool(p, Parameters::kGridGlobalEroded());
  o.maxNodes = Parameters::getInt(p, Parameters::kGridGlobalMaxNodes());
  o.ltmCacheSize = Parameters::getFloat(p, Parameters::kGridGlobalLtmCacheSize());
  o.altitudeDelta = Parameters::getFloat(p, Parameters::kGridGlobalAltitudeDelta());
  return o;
}

// Shared by the 2D grid and the OctoMap: the log-odds sensor model must be usable.
bool validSensorModel(float hit, float miss, float clampMin, float clampMax, float thr,
                      std::ostringstream& r) {
  if (!(hit > 0.5f && hit < 1.0f)) {
    r << "GridGlobal/ProbHit must be above 0.5 and below 1 (got " << hit << ")";
  } else if (!(miss > 0.0f && miss < 0.5f)) {
    r << "GridGlobal/ProbMiss must be above 0 and below 0.5 (got " << miss << ")";
  } else if (!(clampMin > 0.0f && clampMin < clampMax && clampMax < 1.0f)) {
    r << "GridGlobal/ProbClampingMin (" << clampMin << ") and GridGlobal/ProbClampingMax ("
      << clampMax << ") must satisfy 0 < min < max < 1";
  } else if (!(thr >= 0.0f && thr <= 1.0f)) {
    r << "GridGlobal/OccupancyThr must be between 0 and 1 (got " << thr << ")";
  }
  return r.str().empty();
}

bool GlobalGridOptions::IsValid(std::string* why) const {
  std::ostringstream r;
  if (!(std::isfinite(cellSize) && cellSize > 0.0f)) {
    r << "Grid/CellSize must be a finite number > 0 (got " << cellSize << ")";
  } else if (!(std::isfinite(minSize) && minSize >= 0.0f)) {
    r << "GridGlobal/MinSize must be >= 0 (got " << minSize << ")";
  } else if (validSensorModel(probHit, probMiss, probClampingMin, probClampingMax, occupancyThr, r)) {
    if (!(std::isfinite(updateError) && updateError >= 0.0f)) {
      r << "GridGlobal/UpdateError must be >= 0 (got " << updateError << ")";
    } else if (!(std::isfinite(footprintRadius) && footprintRadius >= 0.0f)) {
      r << "GridGlobal/FootprintRadius must be >= 0 (got " << footprintRadius << ")";
    } else if (reassemblyInterval < 1) {
      r << "GridGlobal/ReassemblyInterval must be >= 1 update (got " << reassemblyInterval << ")";
    } else if (maxNodes < 0) {
      r << "GridGlobal/MaxNodes must be >= 0 (got " << maxNodes << ")";
    } else if (!(std::isfinite(altitudeDelta) && altitudeDelta >= 0.0f)) {
      r << "GridGlobal/AltitudeDelta must be >= 0 (got " << altitudeDelta << ")";
    } else if (!(std::isfinite(ltmCacheSize) && ltmCacheSize >= 0.0f && ltmCacheSize < 1e6f)) {
      r << "GridGlobal/LtmCacheSize must be >= 0 MB (got " << ltmCacheSize << ")";
    }
  }
  const std::string text = r.str();
  if (why) *why = text;
  return text.empty();
}

void GlobalGridOptions::validate() const {
  std::string why;
  if (!IsValid(&why)) throw ParameterError("invalid global grid options: " + why);
}

}  // namespace rtabmap

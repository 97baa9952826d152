// Odometry::create: the approach from Odom/Strategy and Reg/Strategy, or by name.
#include <algorithm>
#include <cctype>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/odometry/Odometry.h"
#include "rtabmap_core/odometry/OdometryF2F.h"
#include "rtabmap_core/odometry/OdometryF2M.h"
#include "rtabmap_core/odometry/OdometryS2M.h"
#include "rtabmap_core/odometry/OdometryS2S.h"

namespace rtabmap {

std::string Odometry::typeName(Type type) {
  switch (type) {
    case Type::kF2M: return "F2M";
    case Type::kF2F: return "F2F";
    case Type::kS2M: return "S2M";
    case Type::kS2S: return "S2S";
  }
  return "unknown";
}

Odometry::Type Odometry::typeFromName(const std::string& name) {
  std::string upper = name;
  std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  for (Type t : {Type::kF2M, Type::kF2F, Type::kS2M, Type::kS2S}) {
    if (upper == typeName(t)) return t;
  }
  throw ParameterError("unknown odometry approach '" + name + "' (expected f2m, f2f, s2m or s2s)");
}

std::unique_ptr<Odometry> Odometry::create(Type type, const ParametersMap& parameters) {
  switch (type) {
    case Type::kF2M: return std::make_unique<OdometryF2M>(parameters);
    case Type::kF2F: return std::make_unique<OdometryF2F>(parameters);
    case Type::kS2M: return std::make_unique<OdometryS2M>(parameters);
    case Type::kS2S: return std::make_unique<OdometryS2S>(parameters);
  }
  throw ParameterError("unknown odometry type");
}

std::unique_ptr<Odometry> Odometry::create(const ParametersMap& parameters) {
  Parameters::validate(parameters);
  const int strategy = Parameters::getInt(parameters, Parameters::kOdomStrategy());
  // Reg/Strategy 1 registers scans only: the lidar approaches. Visual (0) and visual-then-ICP
  // (2) odometry are visual: their frames come from cameras.
  const bool lidar = Parameters::getInt(parameters, Parameters::kRegStrategy()) == 1;
  if (lidar) return create(strategy == 0 ? Type::kS2M : Type::kS2S, parameters);
  return create(strategy == 0 ? Type::kF2M : Type::kF2F, parameters);
}

}  // namespace rtabmap

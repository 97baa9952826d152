#include "rtabmap_core/registration/IcpRegistration.h"

#include <chrono>
#include <cmath>

#include "IcpCloud.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap {

IcpOptions IcpOptions::fromParameters(const ParametersMap& p) {
  Parameters::validate(p);
  IcpOptions o;
  o.maxTranslation = Parameters::getFloat(p, Parameters::kIcpMaxTranslation());
  o.maxRotation = Parameters::getFloat(p, Parameters::kIcpMaxRotation());
  o.voxelSize = Parameters::getFloat(p, Parameters::kIcpVoxelSize());
  o.downsamplingStep = Parameters::getInt(p, Parameters::kIcpDownsamplingStep());
  o.rangeMin = Parameters::getFloat(p, Parameters::kIcpRangeMin());
  o.rangeMax = Parameters::getFloat(p, Parameters::kIcpRangeMax());
  o.maxCorrespondenceDistance = Parameters::getFloat(p, Parameters::kIcpMaxCorrespondenceDistance());
  o.iterations = Parameters::getInt(p, Parameters::kIcpIterations());
  o.epsilon = Parameters::getFloat(p, Parameters::kIcpEpsilon());
  o.correspondenceRatio = Parameters::getFloat(p, Parameters::kIcpCorrespondenceRatio());
  o.force4DoF = Parameters::getBool(p, Parameters::kIcpForce4DoF());
  o.force3DoF = Parameters::getBool(p, Parameters::kRegForce3DoF());
  o.pointToPlane = Parameters::getBool(p, Parameters::kIcpPointToPlane());
  o.pointToPlaneK = Parameters::getInt(p, Parameters::kIcpPointToPlaneK());
  o.pointToPlaneRadius = Parameters::getFloat(p, Parameters::kIcpPointToPlaneRadius());
  o.groundNormalsUp = Parameters::getFloat(p, Parameters::kIcpPointToPlaneGroundNormalsUp());
  o.minComplexity = Parameters::getFloat(p, Parameters::kIcpPointToPlaneMinComplexity());
  o.lowComplexityStrategy = Parameters::getInt(p, Parameters::kIcpPointToPlaneLowComplexityStrategy());
  o.maxNormalAngle = Parameters::getFloat(p, Parameters::kIcpPointToPlaneMaxNormalAngle()) * static_cast<float>(M_PI / 180.0);
  return o;
}

bool IcpOptions::IsValid(std::string* why) const {
  const auto fail = [&](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  if (!(maxCorrespondenceDistance > 0.0f)) {
    return fail("Icp/MaxCorrespondenceDistance must be > 0 (no pair could ever be found)");
  }
  if (iterations < 1) return fail("Icp/Iterations must be at least 1");
  if (downsamplingStep < 1) return fail("Icp/DownsamplingStep must be at least 1");
  if (voxelSize < 0.0f || rangeMin < 0.0f || rangeMax < 0.0f || epsilon < 0.0f ||
      maxTranslation < 0.0f || maxRotation < 0.0f || pointToPlaneRadius < 0.0f || maxNormalAngle < 0.0f) {
    return fail("Icp/ sizes, ranges, limits and epsilon must be >= 0");
  }
  if (rangeMax > 0.0f && rangeMin >= rangeMax) {
    return fail("Icp/RangeMin (" + std::to_string(rangeMin) + ") must be below Icp/RangeMax (" +
                std::to_string(rangeMax) + ") or Icp/RangeMax 0 (no limit): no point would remain");
  }
  if (correspondenceRatio < 0.0f || correspondenceRatio > 1.0f) {
    return fail("Icp/CorrespondenceRatio must be in [0, 1]");
  }
  if (pointToPlane && pointToPlaneRadius <= 0.0f && pointToPlaneK < 2) {
    return fail("Icp/PointToPlane needs normals: set Icp/PointToPlaneK >= 2 or Icp/PointToPlaneRadius > 0");
  }
  if (lowComplexityStrategy < 0 || lowComplexityStrategy > 2) {
    return fail("Icp/PointToPlaneLowComplexityStrategy must be 0, 1 or 2");
  }
  if (minComplexity < 0.0f || minComplexity > 1.0f || groundNormalsUp < 0.0f || groundNormalsUp > 1.0f) {
    return fail("Icp/PointToPlaneMinComplexity and Icp/PointToPlaneGroundNormalsUp must be in [0, 1]");
  }
  return true;
}

IcpRegistration::IcpRegistration(const ParametersMap& parameters)
    : IcpRegistration(IcpOptions::fromParameters(parameters)) {}

IcpRegistration::IcpRegistration(const IcpOptions& options) : options_(options) {
  std::string why;
  if (!options_.IsValid(&why)) throw ParameterError("ICP: " + why);
}

Transform IcpRegistration::computeTransform(const LaserScan& from, const LaserScan& to,
                                            const Transform& guess, RegistrationInfo* info) const {
  const auto start = std::chrono::steady_clock::now();
  RegistrationInfo scratch;
  RegistrationInfo& out = info ? *info : scratch;
  icp::IcpCloud target;
  icp::IcpCloud source;
  std::string why;
  // The source needs normals only for the structural complexity, the target for the metric.
  if (!icp::prepareIcpCloud(from, options_, options_.pointToPlane, "from", &target, &why) ||
      !icp::prepareIcpCloud(to, options_, options_.pointToPlane, "to", &source, &why)) {
    out.success = false;
    out.rejectedMsg = why;
    out.totalTimeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return Transform();
  }
  target.buildIndex(options_.maxCorrespondenceDistance);
  Transform t = icp::registerClouds(target, source, guess, options_, &out);
  out.totalTimeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return t;
}

}  // namespace rtabmap

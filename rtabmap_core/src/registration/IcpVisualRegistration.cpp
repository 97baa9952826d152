#include "rtabmap_core/registration/IcpVisualRegistration.h"

#include <chrono>

#include "rtabmap_core/memory/Signature.h"

namespace rtabmap {

IcpVisualRegistration::IcpVisualRegistration(const ParametersMap& parameters)
    : visual_(parameters), icp_(parameters) {}

Transform IcpVisualRegistration::computeTransform(Signature& from, Signature& to, const Transform& guess,
                                                  RegistrationInfo* infoOut) const {
  const auto start = std::chrono::steady_clock::now();
  RegistrationInfo scratch;
  RegistrationInfo& info = infoOut ? *infoOut : scratch;
  const auto elapsed = [&] {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };

  info = RegistrationInfo();
  const Transform visual = visual_.computeTransform(from, to, guess, &info);
  if (visual.isNull()) {
    info.rejectedMsg = "visual: " + info.rejectedMsg;
    info.totalTimeMs = elapsed();
    return Transform();
  }

  std::string problemFrom, problemTo;
  const LaserScan& scanFrom = scanOf(from, &problemFrom);
  const LaserScan& scanTo = scanOf(to, &problemTo);
  const bool fromMissing = scanFrom.empty() || !problemFrom.empty();
  if (fromMissing || scanTo.empty() || !problemTo.empty()) {
    const Signature& node = fromMissing ? from : to;
    const std::string& problem = fromMissing ? problemFrom : problemTo;
    info.success = false;
    info.rejectedMsg = "ICP: Reg/Strategy 2 refines the visual transform with laser scans, but node " +
                       std::to_string(node.id()) + " has none" + (problem.empty() ? "" : " (" + problem + ")");
    info.totalTimeMs = elapsed();
    return Transform();
  }

  RegistrationInfo icpInfo;
  const Transform refined = icp_.computeTransform(scanFrom, scanTo, visual, &icpInfo);
  info.icpCorrespondences = icpInfo.icpCorrespondences;
  info.icpInliersRatio = icpInfo.icpInliersRatio;
  info.icpTranslation = icpInfo.icpTranslation;
  info.icpRotation = icpInfo.icpRotation;
  info.icpStructuralComplexity = icpInfo.icpStructuralComplexity;
  info.icpStructuralDistribution = icpInfo.icpStructuralDistribution;
  info.success = icpInfo.success;
  info.totalTimeMs = elapsed();
  if (refined.isNull()) {
    info.rejectedMsg = "ICP: " + icpInfo.rejectedMsg;
    return Transform();
  }
  info.rejectedMsg.clear();
  info.covariance = icpInfo.covariance;
  return refined;
}

}  // namespace rtabmap

#include "ScanOdometryCommon.h"

#include <cstdio>

#include "rtabmap_core/common/Error.h"

namespace rtabmap::scanodom {

IcpOptions icpOptions(const ParametersMap& parameters) {
  IcpOptions options = IcpOptions::fromParameters(parameters);
  std::string why;
  if (!options.IsValid(&why)) throw ParameterError("lidar odometry: " + why);
  return options;
}

bool prepareFrameScan(SensorData& data, const IcpOptions& options, icp::IcpCloud* scan, std::string* why) {
  if (data.laserScanRaw().empty() && !data.laserScanCompressed().empty()) {
    data.uncompress(false, false, true, false);
  }
  const LaserScan& raw = data.laserScanRaw();
  if (raw.empty()) {
    if (why) {
      // A scan whose every beam was invalid (NaN, out of range) still has its format.
      *why = raw.format() == LaserScan::kUnknown
                 ? "the frame has no laser scan (lidar odometry needs one)"
                 : "scan 'new' is empty (no beam returned a valid range)";
    }
    return false;
  }
  return icp::prepareIcpCloud(data.laserScanRaw(), options, options.pointToPlane, "new", scan, why);
}

Transform registerScan(const icp::IcpCloud& target, const icp::IcpCloud& scan, const Transform& poseGuess,
                       bool unguided, const IcpOptions& options, RegistrationInfo* info) {
  const Transform direct = icp::registerClouds(target, scan, poseGuess, options, info);
  if (!direct.isNull() || !unguided || poseGuess.isInvalid()) return direct;
  const std::string directWhy = info->rejectedMsg;

  IcpOptions coarse = options;
  coarse.maxCorrespondenceDistance = options.maxCorrespondenceDistance * kCoarseFactor;
  icp::IcpCloud wide;  // the same points, indexed for the farther correspondences
  wide.cloud = target.cloud;
  wide.is2d = target.is2d;
  wide.hasNormals = target.hasNormals;
  wide.expectedPoints = target.expectedPoints;
  wide.normalMoment = target.normalMoment;
  wide.normalCount = target.normalCount;
  wide.buildIndex(coarse.maxCorrespondenceDistance);
  RegistrationInfo coarseInfo;
  const Transform start = icp::registerClouds(wide, scan, poseGuess, coarse, &coarseInfo);
  if (start.isNull()) {
    char distance[32];
    std::snprintf(distance, sizeof(distance), "%.3f", coarse.maxCorrespondenceDistance);
    info->rejectedMsg =
        directWhy + " (also with correspondences up to " + distance + " m: " + coarseInfo.rejectedMsg + ")";
    return Transform();
  }
  const Transform refined = icp::registerClouds(target, scan, start, options, info);
  if (refined.isNull()) {
    info->rejectedMsg = directWhy + " (also after a coarse alignment: " + info->rejectedMsg + ")";
  }
  return refined;
}

}  // namespace rtabmap::scanodom

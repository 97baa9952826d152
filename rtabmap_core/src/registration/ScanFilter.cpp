#include "rtabmap_core/registration/ScanFilter.h"

#include "IcpCloud.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap {

ScanFilterOptions ScanFilterOptions::fromParameters(const ParametersMap& parameters) {
  using P = Parameters;
  ScanFilterOptions o;
  o.downsampleStep = P::getInt(parameters, P::kMemLaserScanDownsampleStepSize());
  o.voxelSize = P::getFloat(parameters, P::kMemLaserScanVoxelSize());
  o.normalK = P::getInt(parameters, P::kMemLaserScanNormalK());
  o.normalRadius = P::getFloat(parameters, P::kMemLaserScanNormalRadius());
  std::string why;
  if (!o.IsValid(&why)) throw ParameterError(why);
  return o;
}

bool ScanFilterOptions::IsValid(std::string* why) const {
  const auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (downsampleStep < 1) return fail(Parameters::kMemLaserScanDownsampleStepSize() + " must be >= 1");
  if (!(voxelSize >= 0.0f)) return fail(Parameters::kMemLaserScanVoxelSize() + " must be >= 0");
  if (normalK < 0 || !(normalRadius >= 0.0f)) {
    return fail(Parameters::kMemLaserScanNormalK() + " and " + Parameters::kMemLaserScanNormalRadius() + " must be >= 0");
  }
  return true;
}

LaserScan filterScan(const LaserScan& scan, const ScanFilterOptions& options, std::string* why) {
  // ICP's own preparation does exactly this (IcpCloud.h), in the base frame; IcpOptions'
  // defaults set no range limit.
  IcpOptions icp;
  icp.downsamplingStep = options.downsampleStep;
  icp.voxelSize = options.voxelSize;
  icp.pointToPlaneK = options.normalK;
  icp.pointToPlaneRadius = options.normalRadius;
  const bool normals = scan.hasNormals() || options.wantsNormals();
  icp::IcpCloud prepared;
  if (!icp::prepareIcpCloud(scan, icp, normals, "node", &prepared, why, 1)) return LaserScan();

  // Back to the sensor's frame, so the scan keeps its local transform (the sensor's height and
  // position on the robot, where the local grid casts its rays from).
  const Transform& local = scan.localTransform().isNull() ? Transform::Identity() : scan.localTransform();
  const Eigen::Matrix3f Rt = local.rotationMatrix().cast<float>().transpose();
  const Eigen::Vector3f t = local.translation().cast<float>();
  for (icp::Point& p : *prepared.cloud) {
    if (prepared.is2d) p.z = t.z();  // the plane the scan lies in (prepareIcpCloud flattened it)
    p.getVector3fMap() = Rt * (p.getVector3fMap() - t);
    if (normals) p.getNormalVector3fMap() = Rt * p.getNormalVector3fMap();
  }
  const LaserScan out = icp::toLaserScan(*prepared.cloud, prepared.is2d, normals, prepared.expectedPoints);
  return LaserScan(out.data(), out.maxPoints(), scan.rangeMin(), scan.rangeMax(), out.format(), local);
}

}  // namespace rtabmap

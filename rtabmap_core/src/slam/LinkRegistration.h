#pragma once
// The transform of a new link (loop closure, proximity, refined neighbour) between two nodes,
// by the registration Reg/Strategy names: 0 visual, 1 ICP on the laser scans (needs a guess),
// 2 visual refined by ICP. Private to the slam area.
#include <Eigen/Core>

#include <memory>
#include <string>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"
#include "rtabmap_core/params/Parameters.h"
#include "rtabmap_core/registration/RegistrationInfo.h"

namespace rtabmap {

class Signature;
class RegistrationVis;
class IcpRegistration;
class IcpVisualRegistration;

class LinkRegistration {
 public:
  // Throws ParameterError on invalid Reg/, Vis/ or Icp/ parameters.
  explicit LinkRegistration(const ParametersMap& parameters);
  ~LinkRegistration();

  int strategy() const { return strategy_; }
  bool usesVision() const { return strategy_ != 1; }
  bool usesScans() const { return strategy_ != 0; }
  // Visual registration that reads the nodes' images beside their words (RegistrationVis).
  bool visualNeedsImages() const;
  // Icp/PointToPlaneMinComplexity of the ICP used with Icp/PointToPlane (0 otherwise: ICP then
  // does not measure complexity).
  float minComplexity() const;
  // Icp/MaxCorrespondenceDistance: how far from its guess ICP can pull a scan (0 without ICP).
  float icpReach() const;
  // Icp/VoxelSize (0 without ICP).
  float icpVoxelSize() const;
  // The visual registration of Reg/Strategy 0 (null with ICP in the strategy), and Reg/RepeatOnce.
  const RegistrationVis* visualOnly() const { return visual_.get(); }
  bool repeatOnce() const { return repeatOnce_; }

  // Pose of `to`'s base in `from`'s base (to = from * T), null with info->rejectedMsg on
  // failure. `guess` null = none (ICP alone then refuses: it only refines a guess; a visual
  // result is registered once more from itself, Reg/RepeatOnce). The nodes' sensor data may
  // gain cached features and uncompressed scans.
  Transform compute(Signature& from, Signature& to, const Transform& guess, RegistrationInfo* info) const;
  // ICP of the two nodes' laser scans from `guess` alone, whatever the strategy (1 or 2).
  Transform computeIcp(Signature& from, Signature& to, const Transform& guess, RegistrationInfo* info) const;
  // ICP of two scans (each with its local transform), from `guess`.
  Transform icp(const LaserScan& from, const LaserScan& to, const Transform& guess, RegistrationInfo* info) const;

 private:
  int strategy_;
  bool repeatOnce_;  // Reg/RepeatOnce
  std::unique_ptr<RegistrationVis> visual_;
  std::unique_ptr<IcpRegistration> icp_;
  std::unique_ptr<IcpVisualRegistration> visualIcp_;
};

// Information matrix (inverse covariance) of a link. Variances are floored at 1e-9 so a perfect
// match never becomes an infinitely stiff constraint; diagonalOnly drops the correlations
// (Mem/CovOffDiagIgnored).
Link::InfMatrix informationOf(const Eigen::Matrix<double, 6, 6>& covariance, bool diagonalOnly);

}  // namespace rtabmap

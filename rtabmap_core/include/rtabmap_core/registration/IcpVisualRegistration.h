#pragma once
// Visual-then-ICP registration (Reg/Strategy 2, JFR 2019 3.1.2): the visual registration finds
// the transform between two nodes from their image features, wherever the robot was (a loop
// closure has no motion guess), and ICP on the two nodes' laser scans refines it from there.
// Vision brings the global correspondence a lidar cannot (corridors look alike), ICP the
// centimetre accuracy a camera's depth cannot.
//
// The result's covariance and ICP fields come from the ICP step, its visual fields (matches,
// inliers) from the visual step. It fails, with the step's reason, if either step does.
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/params/Parameters.h"
#include "rtabmap_core/registration/IcpRegistration.h"
#include "rtabmap_core/registration/RegistrationInfo.h"
#include "rtabmap_core/registration/RegistrationVis.h"

namespace rtabmap {

class Signature;

class IcpVisualRegistration {
 public:
  // Vis/*, Icp/* and Reg/*; throws ParameterError on invalid values.
  explicit IcpVisualRegistration(const ParametersMap& parameters = {});

  const RegistrationVis& visual() const { return visual_; }
  const IcpRegistration& icp() const { return icp_; }

  // The pose of `to`'s base frame in `from`'s, as every registration here. `guess` (null =
  // none) only guides the visual matching. Features are extracted and stored in the nodes'
  // sensor data when missing (see RegistrationVis); compressed scans are uncompressed.
  // Null with info->rejectedMsg ("visual: ...", "ICP: ...") on failure. Never throws on bad
  // sensor data.
  Transform computeTransform(Signature& from, Signature& to, const Transform& guess = Transform(),
                             RegistrationInfo* info = nullptr) const;

 private:
  RegistrationVis visual_;
  IcpRegistration icp_;
};

}  // namespace rtabmap

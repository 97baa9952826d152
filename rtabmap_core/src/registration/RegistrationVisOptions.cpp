#include "rtabmap_core/registration/RegistrationVis.h"

namespace rtabmap {

RegistrationVisOptions RegistrationVisOptions::fromParameters(const ParametersMap& p) {
  RegistrationVisOptions o;
  o.features = FeatureOptions::fromParameters(p, FeatureGroup::kVis);
  o.correspondences = CorrespondenceOptions::fromParameters(p);
  o.estimationType = Parameters::getInt(p, Parameters::kVisEstimationType());
  o.minInliers = Parameters::getInt(p, Parameters::kVisMinInliers());
  o.pnp.reprojError = Parameters::getFloat(p, Parameters::kVisPnPReprojError());
  o.pnp.iterations = Parameters::getInt(p, Parameters::kVisIterations());
  o.pnp.flags = Parameters::getInt(p, Parameters::kVisPnPFlags());
  o.pnp.refineIterations = Parameters::getInt(p, Parameters::kVisPnPRefineIterations());
  o.pnp.shuffleSeed = Parameters::getInt(p, Parameters::kVisPnPShuffleSeed());
  o.pnp.minInliers = o.minInliers;
  o.rigid.inlierDistance = Parameters::getFloat(p, Parameters::kVisInlierDistance());
  o.rigid.iterations = o.pnp.iterations;
  o.rigid.refineIterations = Parameters::getInt(p, Parameters::kVisRefineIterations());
  o.rigid.minInliers = o.minInliers;
  o.forwardEstOnly = Parameters::getBool(p, Parameters::kVisForwardEstOnly());
  o.meanInliersDistance = Parameters::getFloat(p, Parameters::kVisMeanInliersDistance());
  o.minInliersDistribution = Parameters::getFloat(p, Parameters::kVisMinInliersDistribution());
  o.bundleAdjustment = Parameters::getInt(p, Parameters::kVisBundleAdjustment());
  o.force3DoF = Parameters::getBool(p, Parameters::kRegForce3DoF());
  return o;
}

bool RegistrationVisOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  std::string sub;
  if (!features.IsValid(&sub)) return fail(sub);
  if (!correspondences.IsValid(&sub)) return fail(sub);
  if (estimationType != 0 && estimationType != 1) return fail("Vis/EstimationType must be 0 (3D->3D) or 1 (PnP)");
  if (!pnp.IsValid(&sub)) return fail(sub);
  if (!rigid.IsValid(&sub)) return fail(sub);
  if (minInliers < 0) return fail("Vis/MinInliers must not be negative");
  if (meanInliersDistance < 0.0f) return fail("Vis/MeanInliersDistance must not be negative");
  if (minInliersDistribution < 0.0f || minInliersDistribution > 0.5f) {
    return fail("Vis/MinInliersDistribution must be in [0, 0.5]");
  }
  if (bundleAdjustment != 0 && bundleAdjustment != 3) return fail("Vis/BundleAdjustment must be 0 or 3 (Ceres)");
  if (correspondences.type == 1 && features.maxFeatures < 0) {
    return fail("optical flow (Vis/CorType 1) needs keypoints to track: Vis/MaxFeatures must not be negative");
  }
  return true;
}

}  // namespace rtabmap

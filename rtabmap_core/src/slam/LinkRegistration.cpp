#include "LinkRegistration.h"

#include <Eigen/LU>

#include <algorithm>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/memory/Signature.h"
#include "rtabmap_core/registration/IcpRegistration.h"
#include "rtabmap_core/registration/IcpVisualRegistration.h"
#include "rtabmap_core/registration/RegistrationVis.h"

namespace rtabmap {

LinkRegistration::LinkRegistration(const ParametersMap& parameters)
    : strategy_(Parameters::getInt(parameters, Parameters::kRegStrategy())),
      repeatOnce_(Parameters::getBool(parameters, Parameters::kRegRepeatOnce())) {
  switch (strategy_) {
    case 0:
      visual_ = std::make_unique<RegistrationVis>(parameters);
      break;
    case 1:
      icp_ = std::make_unique<IcpRegistration>(parameters);
      break;
    case 2:
      visualIcp_ = std::make_unique<IcpVisualRegistration>(parameters);
      break;
    default:
      throw ParameterError(Parameters::kRegStrategy() + " must be 0 (visual), 1 (ICP) or 2 (visual then ICP), not " +
                           std::to_string(strategy_));
  }
}

LinkRegistration::~LinkRegistration() = default;

Transform LinkRegistration::compute(Signature& from, Signature& to, const Transform& guess, RegistrationInfo* info) const {
  RegistrationInfo scratch;
  RegistrationInfo& out = info ? *info : scratch;
  out = RegistrationInfo();
  if (!usesVision()) return computeIcp(from, to, guess, &out);
  auto visual = [&](const Transform& g) {
    return visual_ ? visual_->computeTransform(from, to, g, &out) : visualIcp_->computeTransform(from, to, g, &out);
  };
  const Transform first = visual(guess);
  if (!repeatOnce_ || !guess.isNull() || first.isNull()) return first;
  // Reg/RepeatOnce: found without a guess (a loop closure), the transform is registered again
  // from itself: the features are then matched where it projects them (Vis/CorGuessWinSize),
  // which finds the correspondences descriptor matching alone missed and refines the estimate.
  // A wrong first transform (a look-alike place) rarely survives it: its projections land on
  // the wrong features, and too few inliers are left.
  out = RegistrationInfo();
  const Transform second = visual(first);
  if (second.isNull()) out.rejectedMsg = "registered again from its own first estimate (Reg/RepeatOnce): " + out.rejectedMsg;
  return second;
}

Transform LinkRegistration::computeIcp(Signature& from, Signature& to, const Transform& guess,
                                       RegistrationInfo* info) const {
  RegistrationInfo scratch;
  RegistrationInfo& out = info ? *info : scratch;
  out = RegistrationInfo();
  if (!usesScans()) {
    out.rejectedMsg = "scan matching needs Reg/Strategy 1 or 2";
    return Transform();
  }
  if (guess.isNull()) {
    out.rejectedMsg = "ICP only refines a motion guess and none was given";
    return Transform();
  }
  std::string problem;
  const LaserScan& a = scanOf(from, &problem);
  const LaserScan& b = scanOf(to, &problem);
  if (a.empty() || b.empty()) {
    out.rejectedMsg = "ICP: node " + std::to_string(a.empty() ? from.id() : to.id()) + " has no laser scan" +
                      (problem.empty() ? std::string() : " (" + problem + ")");
    return Transform();
  }
  return icp(a, b, guess, &out);
}

Transform LinkRegistration::icp(const LaserScan& from, const LaserScan& to, const Transform& guess,
                                RegistrationInfo* info) const {
  if (icp_) return icp_->computeTransform(from, to, guess, info);
  if (visualIcp_) return visualIcp_->icp().computeTransform(from, to, guess, info);
  if (info) info->rejectedMsg = "scan matching needs Reg/Strategy 1 or 2";
  return Transform();
}

bool LinkRegistration::visualNeedsImages() const {
  const RegistrationVis* v = visual_ ? visual_.get() : visualIcp_ ? &visualIcp_->visual() : nullptr;
  return v && v->needsImages();
}

float LinkRegistration::minComplexity() const {
  // ICP measures structural complexity from normals: point-to-plane only.
  const IcpOptions* o = icp_ ? &icp_->options() : visualIcp_ ? &visualIcp_->icp().options() : nullptr;
  return o && o->pointToPlane ? o->minComplexity : 0.0f;
}

float LinkRegistration::icpReach() const {
  const IcpOptions* o = icp_ ? &icp_->options() : visualIcp_ ? &visualIcp_->icp().options() : nullptr;
  return o ? o->maxCorrespondenceDistance : 0.0f;
}

float LinkRegistration::icpVoxelSize() const {
  const IcpOptions* o = icp_ ? &icp_->options() : visualIcp_ ? &visualIcp_->icp().options() : nullptr;
  return o ? o->voxelSize : 0.0f;
}

Link::InfMatrix informationOf(const Eigen::Matrix<double, 6, 6>& covariance, bool diagonalOnly) {
  Eigen::Matrix<double, 6, 6> c = covariance;
  if (diagonalOnly || !c.allFinite()) c = Eigen::Matrix<double, 6, 6>(c.diagonal().asDiagonal());
  for (int i = 0; i < 6; ++i) {
    if (!std::isfinite(c(i, i)) || c(i, i) < 1e-9) c(i, i) = 1e-9;
  }
  Link::InfMatrix inf = c.inverse();
  if (!inf.allFinite()) {
    inf.setZero();
    for (int i = 0; i < 6; ++i) inf(i, i) = 1.0 / c(i, i);
  }
  return 0.5 * (inf + inf.transpose());
}

}  // namespace rtabmap

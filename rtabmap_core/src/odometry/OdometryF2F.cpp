// Frame-to-frame visual odometry (JFR 2019, 3.1.1).
#include "rtabmap_core/odometry/OdometryF2F.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "VisualInput.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap {

using odometry_detail::VisualOdometryOptions;

namespace {

RegistrationVisOptions matchingOptions(const ParametersMap& p) {
  RegistrationVisOptions o = RegistrationVisOptions::fromParameters(p);
  o.correspondences.type = 0;
  return o;
}

}  // namespace

struct OdometryF2F::Impl {
  explicit Impl(const ParametersMap& p)
      : vo(VisualOdometryOptions::fromParameters(p)), registration(p), matching(matchingOptions(p)) {
    std::string why;
    if (!vo.IsValid(&why)) throw ParameterError("F2F odometry: " + why);
  }
  VisualOdometryOptions vo;
  RegistrationVis registration;  // Vis/ as given (optical flow with Vis/CorType 1)
  RegistrationVis matching;      // descriptor matching: the fallback of optical flow
  VisualFrame keyFrame;
  Transform keyFramePose;
  int keyFramesAdded = 0;
};

OdometryF2F::OdometryF2F(const ParametersMap& parameters)
    : Odometry(parameters), impl_(std::make_unique<Impl>(parameters)) {}

OdometryF2F::~OdometryF2F() = default;

bool OdometryF2F::needsInitialisation() const { return impl_->keyFramePose.isNull(); }

void OdometryF2F::resetMap(const Transform&) {
  impl_->keyFrame = VisualFrame();
  impl_->keyFramePose = Transform();
  impl_->keyFramesAdded = 0;
}

Transform OdometryF2F::keyFramePose() const { return impl_->keyFramePose; }
int OdometryF2F::keyFramesAdded() const { return impl_->keyFramesAdded; }

Transform OdometryF2F::computeTransform(SensorData& data, const Transform& guess, OdometryInfo* info) {
  Impl& m = *impl_;
  odometry_detail::PreparedVisualFrame prepared =
      odometry_detail::prepareVisualFrame(data, m.registration.detector(), m.vo.decimation);
  if (!prepared.problem.empty()) {
    info->lostReason = prepared.problem;
    return Transform();
  }
  VisualFrame& frame = prepared.frame;
  info->features = static_cast<int>(frame.keypoints.size());
  if (m.keyFramePose.isNull()) {
    const int minInliers = std::max(1, m.registration.options().minInliers);
    const int with3D = static_cast<int>(std::count_if(frame.points3D.begin(), frame.points3D.end(), [](const cv::Point3f& p) {
      return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    }));
    if (with3D < minInliers) {
      std::ostringstream s;
      s << "only " << with3D << " features with depth: not enough for a key frame (Vis/MinInliers " << minInliers << ")";
      info->lostReason = s.str();
      return Transform();
    }
    m.keyFrame = std::move(frame);
    m.keyFramePose = getPose();
    ++m.keyFramesAdded;
    info->keyFrameAdded = true;
    info->localKeyFrames = 1;
    return Transform::Identity();
  }
  // The guess is relative to the previous frame; registration wants it from the key frame.
  const Transform guessFromKey = guess.isNull() ? Transform() : m.keyFramePose.inverse() * getPose() * guess;
  Transform motion = m.registration.computeTransform(m.keyFrame, frame, guessFromKey, &info->reg);
  if (motion.isNull() && m.registration.options().correspondences.type == 1) {
    const std::string flowFailure = info->reg.rejectedMsg;
    motion = m.matching.computeTransform(m.keyFrame, frame, guessFromKey, &info->reg);
    if (motion.isNull()) info->reg.rejectedMsg += " (optical flow before: " + flowFailure + ")";
  }
  if (motion.isNull()) {
    info->lostReason = "registration with the key frame failed: " + info->reg.rejectedMsg;
    return Transform();
  }
  const Transform pose = m.keyFramePose * motion;
  if (m.vo.needsKeyFrame(info->reg.inliers, static_cast<int>(m.keyFrame.keypoints.size()))) {
    m.keyFrame = std::move(frame);
    m.keyFramePose = pose;
    ++m.keyFramesAdded;
    info->keyFrameAdded = true;
  }
  info->localKeyFrames = 1;
  info->covariance = info->reg.covariance;
  if (!m.vo.fillInfoData) info->reg.matchesIDs.clear(), info->reg.inliersIDs.clear();
  return getPose().inverse() * pose;
}

}  // namespace rtabmap

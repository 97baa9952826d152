// Frame-to-map visual odometry (JFR 2019, 3.1.1).
#include "rtabmap_core/odometry/OdometryF2M.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_set>

#include "VisualInput.h"
#include "VisualLocalMap.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap {

using odometry_detail::VisualLocalMap;
using odometry_detail::VisualOdometryOptions;

struct OdometryF2M::Impl {
  explicit Impl(const ParametersMap& p)
      : vo(VisualOdometryOptions::fromParameters(p)),
        registration(odometry_detail::mapRegistrationOptions(p)),
        maxSize(Parameters::getInt(p, Parameters::kOdomF2MMaxSize())),
        maxNewFeatures(Parameters::getInt(p, Parameters::kOdomF2MMaxNewFeatures())),
        bundleAdjustment(Parameters::getInt(p, Parameters::kOdomF2MBundleAdjustment())),
        bundleMaxFrames(Parameters::getInt(p, Parameters::kOdomF2MBundleAdjustmentMaxFrames())) {
    std::string why;
    if (!vo.IsValid(&why)) throw ParameterError("F2M odometry: " + why);
    ba.huberPixels = registration.options().pnp.reprojError;
    ba.iterations = 10;
  }

  VisualOdometryOptions vo;
  RegistrationVis registration;
  int maxSize;
  int maxNewFeatures;
  int bundleAdjustment;
  int bundleMaxFrames;
  BundleAdjustmentOptions ba;
  VisualLocalMap map;
  int frameCounter = 0;
  int keyFramesAdded = 0;

  // Key frames kept: those bundle adjustment works on, else only the last (the reference of
  // the key-frame decision).
  int keyFramesKept() const { return bundleAdjustment == 3 ? bundleMaxFrames : 1; }

  struct KeyFrameDraft;
  // Empty if the frame has enough 3D features to start the map, else why not.
  std::string cannotStartMap(const VisualFrame& frame) const;
  // Pose of the frame registered with the map (null with info->lostReason on failure); the
  // inliers refresh their map points and go into the draft.
  Transform registerWithMap(const VisualFrame& frame, const Transform& guessPose, OdometryInfo* info,
                            KeyFrameDraft& draft);
  // The frame becomes a key frame at `pose`: new map points, trimming, local bundle adjustment
  // (OdomF2M/BundleAdjustment 3). Returns the pose, refined by the adjustment.
  Transform addKeyFrame(const VisualFrame& frame, Transform pose, KeyFrameDraft& draft, OdometryInfo* info);
};

namespace {

bool finite3(const cv::Point3f& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

cv::Point3f transformPoint(const Transform& T, const cv::Point3f& p) {
  const Eigen::Vector3d q = T.toEigen() * Eigen::Vector3d(p.x, p.y, p.z);
  return cv::Point3f(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
}

float depthInCamera(const VisualFrame& frame, size_t i) {
  if (i >= frame.points3D.size() || !finite3(frame.points3D[i])) return 0.0f;
  const cv::Point3f c = transformPoint(frame.model.localTransform().inverse(), frame.points3D[i]);
  return c.z > 0.0f ? c.z : 0.0f;
}

// Indices of the frame's features with a 3D point that `taken` does not exclude, strongest
// first, at most `limit` (0 = all).
std::vector<size_t> newFeatureCandidates(const VisualFrame& frame, const std::vector<char>& taken, int limit) {
  std::vector<size_t> candidates;
  for (size_t i = 0; i < frame.keypoints.size(); ++i) {
    if (!taken[i] && i < frame.points3D.size() && finite3(frame.points3D[i])) candidates.push_back(i);
  }
  std::stable_sort(candidates.begin(), candidates.end(), [&](size_t a, size_t b) {
    return frame.keypoints[a].response > frame.keypoints[b].response;
  });
  if (limit > 0 && candidates.size() > static_cast<size_t>(limit)) candidates.resize(static_cast<size_t>(limit));
  return candidates;
}

}  // namespace

OdometryF2M::OdometryF2M(const ParametersMap& parameters)
    : Odometry(parameters), impl_(std::make_unique<Impl>(parameters)) {}

OdometryF2M::~OdometryF2M() = default;

bool OdometryF2M::needsInitialisation() const { return impl_->map.empty(); }

void OdometryF2M::resetMap(const Transform&) {
  impl_->map.clear();
  impl_->frameCounter = 0;
  impl_->keyFramesAdded = 0;
}

std::vector<cv::Point3f> OdometryF2M::localMapPoints() const {
  std::vector<cv::Point3f> points;
  for (const auto& [id, p] : impl_->map.points()) points.push_back(p.position);
  return points;
}

int OdometryF2M::localMapSize() const { return static_cast<int>(impl_->map.size()); }
int OdometryF2M::keyFramesAdded() const { return impl_->keyFramesAdded; }

// A key frame in the making: the map points the frame observes and where.
struct OdometryF2M::Impl::KeyFrameDraft {
  std::vector<char> taken;       // per feature: matched to a map point (not added again)
  std::unordered_set<int> keep;  // map points the frame observes: trimmed last
  VisualLocalMap::KeyFrame keyFrame;
};

std::string OdometryF2M::Impl::cannotStartMap(const VisualFrame& frame) const {
  const int minInliers = std::max(1, registration.options().minInliers);
  int with3D = 0;
  for (const cv::Point3f& p : frame.points3D) with3D += finite3(p) ? 1 : 0;
  if (with3D >= minInliers) return std::string();
  std::ostringstream s;
  s << "only " << with3D << " features with depth: not enough to start the map (Vis/MinInliers " << minInliers << ")";
  return s.str();
}

Transform OdometryF2M::Impl::registerWithMap(const VisualFrame& frame, const Transform& guessPose, OdometryInfo* info,
                                             KeyFrameDraft& draft) {
  VisualCorrespondences correspondences;
  const std::vector<int> mapIds = map.asFrame().ids;  // the map changes below
  const Transform pose = registration.computeTransform(map.asFrame(), frame, guessPose, &info->reg, &correspondences);
  if (pose.isNull()) {
    info->lostReason = "registration with the local map failed: " + info->reg.rejectedMsg;
    return pose;
  }
  // Inliers refresh their map point (age, descriptor) and are observations of a key frame.
  for (int k : correspondences.inliers) {
    const cv::DMatch& match = correspondences.matches[static_cast<size_t>(k)];
    const int id = mapIds[static_cast<size_t>(match.queryIdx)];
    const size_t feature = static_cast<size_t>(match.trainIdx);
    map.observe(id, frameCounter, frame.descriptors.row(match.trainIdx));
    draft.taken[feature] = 1;
    draft.keep.insert(id);
    draft.keyFrame.observations[id] = {frame.keypoints[feature].pt, depthInCamera(frame, feature)};
  }
  return pose;
}

Transform OdometryF2M::Impl::addKeyFrame(const VisualFrame& frame, Transform pose, KeyFrameDraft& draft,
                                         OdometryInfo* info) {
  // The unmatched features with depth join the map.
  for (size_t i : newFeatureCandidates(frame, draft.taken, map.empty() ? maxSize : maxNewFeatures)) {
    const int id = map.addPoint(transformPoint(pose, frame.points3D[i]), frame.descriptors.row(static_cast<int>(i)),
                                frameCounter);
    draft.keep.insert(id);
    draft.keyFrame.observations[id] = {frame.keypoints[i].pt, depthInCamera(frame, i)};
  }
  draft.keyFrame.pose = pose;
  map.addKeyFrame(std::move(draft.keyFrame), keyFramesKept());
  map.trim(static_cast<size_t>(std::max(0, maxSize)), draft.keep);
  ++keyFramesAdded;
  info->keyFrameAdded = true;
  // The key frames' observations are pixels of one camera model: with several cameras side
  // by side the adjustment would project every point through the first camera, so it is skipped.
  if (bundleAdjustment == 3 && frame.severalCameras()) {
    RTABMAP_DEBUG("F2M local bundle adjustment skipped: it supports one camera per frame, this one has "
                  << frame.models.size());
  } else if (bundleAdjustment == 3) {
    const BundleAdjustmentSummary s = map.adjust(bundleMaxFrames, ba);
    if (s.success) {
      pose = map.keyFrames().back().pose;
    } else {
      RTABMAP_DEBUG("F2M local bundle adjustment skipped: " << s.message);
    }
  }
  return pose;
}

Transform OdometryF2M::computeTransform(SensorData& data, const Transform& guess, OdometryInfo* info) {
  Impl& m = *impl_;
  ++m.frameCounter;
  const odometry_detail::PreparedVisualFrame prepared =
      odometry_detail::prepareVisualFrame(data, m.registration.detector(), m.vo.decimation);
  if (!prepared.problem.empty()) {
    info->lostReason = prepared.problem;
    return Transform();
  }
  const VisualFrame& frame = prepared.frame;
  info->features = static_cast<int>(frame.keypoints.size());
  Impl::KeyFrameDraft draft;
  draft.taken.assign(frame.keypoints.size(), 0);
  draft.keyFrame.model = frame.model;
  draft.keyFrame.baseline = frame.stereoBaseline;
  draft.keyFrame.features = info->features;

  Transform pose;
  bool keyFrame = true;
  if (m.map.empty()) {
    // First frame: its 3D features start the map at the current pose.
    info->lostReason = m.cannotStartMap(frame);
    if (!info->lostReason.empty()) return Transform();
    pose = getPose();
  } else {
    pose = m.registerWithMap(frame, guess.isNull() ? Transform() : getPose() * guess, info, draft);
    if (pose.isNull()) return pose;
    const int reference = m.map.keyFrames().empty() ? info->features : m.map.keyFrames().back().features;
    keyFrame = m.vo.needsKeyFrame(info->reg.inliers, reference);
  }
  if (keyFrame) pose = m.addKeyFrame(frame, pose, draft, info);
  info->localMapSize = static_cast<int>(m.map.size());
  info->localKeyFrames = static_cast<int>(m.map.keyFrames().size());
  info->covariance = info->reg.success ? info->reg.covariance : Eigen::Matrix<double, 6, 6>::Identity();
  if (!m.vo.fillInfoData) info->reg.matchesIDs.clear(), info->reg.inliersIDs.clear();
  return getPose().inverse() * pose;
}

}  // namespace rtabmap

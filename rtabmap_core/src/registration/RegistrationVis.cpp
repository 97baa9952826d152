#include "rtabmap_core/registration/RegistrationVis.h"

#include <opencv2/core.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/memory/Signature.h"
#include "rtabmap_core/registration/BundleAdjustment.h"

namespace rtabmap {
namespace {

using Clock = std::chrono::steady_clock;

bool finite3(const cv::Point3f& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

const cv::Point3f kNoPoint(std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::quiet_NaN(),
                           std::numeric_limits<float>::quiet_NaN());

cv::Point3f pointOf(const std::vector<cv::Point3f>& points, int i) {
  return i >= 0 && static_cast<size_t>(i) < points.size() ? points[static_cast<size_t>(i)] : kNoPoint;
}

cv::Point3f transformPoint(const Eigen::Isometry3d& T, const cv::Point3f& p) {
  const Eigen::Vector3d q = T * Eigen::Vector3d(p.x, p.y, p.z);
  return cv::Point3f(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
}

// Where each reference point falls in the new image under the guess; NaN when it is unknown,
// behind every camera or outside every camera's image. With several cameras the point goes to
// the first camera that sees it, its u offset into that camera's sub-image.
std::vector<cv::Point2f> projectReference(const VisualFrame& from, const VisualFrame& to, const Transform& guess) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<cv::Point2f> projected(from.size(), cv::Point2f(nan, nan));
  const std::vector<CameraModel> cameras = to.models.empty() ? std::vector<CameraModel>{to.model} : to.models;
  const int w = to.cameraWidth();
  const int h = to.model.imageHeight() > 0 ? to.model.imageHeight() : to.grey.rows;
  for (size_t c = 0; c < cameras.size(); ++c) {
    const CameraModel& m = cameras[c];
    const Eigen::Isometry3d worldToCamera = (guess * m.localTransform()).inverse().toEigen();
    const double offset = static_cast<double>(c) * w;
    for (size_t i = 0; i < projected.size() && i < from.points3D.size(); ++i) {
      const cv::Point3f& p = from.points3D[i];
      if (!finite3(p) || std::isfinite(projected[i].x)) continue;
      const Eigen::Vector3d q = worldToCamera * Eigen::Vector3d(p.x, p.y, p.z);
      if (q.z() <= 0.0) continue;
      const double u = m.fx() * q.x() / q.z() + m.cx();
      const double v = m.fy() * q.y() / q.z() + m.cy();
      if (w > 0 && h > 0 && (u < 0.0 || v < 0.0 || u > w - 1 || v > h - 1)) continue;
      projected[i] = cv::Point2f(static_cast<float>(u + offset), static_cast<float>(v));
    }
  }
  return projected;
}

// Standard deviation along the least spread direction of the inliers' image positions
// normalised by the image size: near 0 when they lie on a line or in a corner (a poorly
// constrained transform), about 0.29 when they cover the image uniformly.
double inliersDistribution(const std::vector<cv::Point2f>& points, const std::vector<int>& inliers, const cv::Size& size) {
  if (size.width <= 0 || size.height <= 0 || inliers.size() < 3) return 0.0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int i : inliers) mean += Eigen::Vector2d(points[static_cast<size_t>(i)].x / size.width, points[static_cast<size_t>(i)].y / size.height);
  mean /= static_cast<double>(inliers.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (int i : inliers) {
    const Eigen::Vector2d d = Eigen::Vector2d(points[static_cast<size_t>(i)].x / size.width, points[static_cast<size_t>(i)].y / size.height) - mean;
    cov += d * d.transpose();
  }
  cov /= static_cast<double>(inliers.size());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  return std::sqrt(std::max(0.0, eig.eigenvalues()(0)));
}

// Depth along the optical axis of a base-frame point seen by a camera with this local transform.
float depthInCamera(const cv::Point3f& p, const Transform& local) {
  if (!finite3(p)) return 0.0f;
  const Eigen::Vector3d c = local.inverse().toEigen() * Eigen::Vector3d(p.x, p.y, p.z);
  return c.z() > 0.0 ? static_cast<float>(c.z()) : 0.0f;
}


// ---- Stages of a registration ------------------------------------------------------------------

// FrameMatches found between the two frames, with the new frame's side of each match.
struct FrameMatches {
  std::vector<cv::DMatch> matches;     // queryIdx: from feature, trainIdx: to feature (flow: from index)
  std::vector<cv::Point2f> toPoints;   // per match, in the new image
  std::vector<cv::Point3f> toPoints3D; // per match, new base frame; NaN when unknown
  bool flow = false;
  std::string problem;                 // non-empty: no correspondence could be searched, and why
};

// Optical flow of the reference keypoints into the new image (Vis/CorType 1), started at
// their predicted positions when there is a guess.
FrameMatches trackByOpticalFlow(const VisualFrame& from, const VisualFrame& to, const Transform& guess,
                                   const RegistrationVisOptions& options) {
  FrameMatches c;
  c.flow = true;
  std::vector<cv::Point2f> fromPoints;
  cv::KeyPoint::convert(from.keypoints, fromPoints);
  std::vector<cv::Point2f> initial;
  if (!guess.isNull()) initial = projectReference(from, to, guess);
  if (initial.size() != fromPoints.size()) initial.clear();
  std::vector<unsigned char> status;
  const std::vector<cv::Point2f> tracked =
      trackOpticalFlow(from.grey, to.grey, fromPoints, initial, options.correspondences, status);
  std::vector<cv::KeyPoint> trackedKeypoints;
  for (size_t i = 0; i < status.size(); ++i) {
    if (!status[i]) continue;
    if (to.severalCameras() && to.cameraOf(tracked[i].x) != from.cameraOf(fromPoints[i].x)) continue;
    c.matches.emplace_back(static_cast<int>(i), static_cast<int>(i), 0.0f);
    c.toPoints.push_back(tracked[i]);
    trackedKeypoints.emplace_back(tracked[i], from.keypoints[i].size);
  }
  // The tracked points are new image points: their 3D comes from the new frame's depth or
  // stereo pair, needed only by the estimators that use the new frame's 3D.
  if (to.points3DAt && (options.estimationType == 0 || !options.forwardEstOnly || to.severalCameras())) {
    c.toPoints3D = to.points3DAt(trackedKeypoints);
  } else {
    c.toPoints3D.assign(c.toPoints.size(), kNoPoint);
  }
  return c;
}

// NNDR descriptor matching (Vis/CorType 0): within Vis/CorGuessWinSize of each reference
// point's predicted position when there is a guess, else over the whole image.
FrameMatches matchByDescriptors(const VisualFrame& from, const VisualFrame& to, const Transform& guess,
                                   const RegistrationVisOptions& options) {
  FrameMatches c;
  const bool guided = !guess.isNull() && options.correspondences.guessWinSize > 0 && !from.points3D.empty();
  if ((from.descriptors.empty() || to.descriptors.empty()) && !from.ids.empty() && !to.ids.empty()) {
    // Words of nodes without descriptors (Mem/RawDescriptorsKept false): paired by word id.
    c.matches = matchByWordIds(from.ids, to.ids, guided ? projectReference(from, to, guess) : std::vector<cv::Point2f>(),
                               to.keypoints, static_cast<float>(options.correspondences.guessWinSize));
  } else if (from.descriptors.empty() || to.descriptors.empty()) {
    c.problem = "a frame has keypoints but no descriptors";
    return c;
  } else if (from.descriptors.type() != to.descriptors.type() || from.descriptors.cols != to.descriptors.cols) {
    c.problem = "the two frames' descriptors differ in type or length (extracted with different Vis/FeatureType?)";
    return c;
  } else if (guided) {
    c.matches = matchByProjection(projectReference(from, to, guess), from.descriptors, to.keypoints, to.descriptors,
                                  static_cast<float>(options.correspondences.guessWinSize), options.correspondences);
  } else {
    c.matches = matchDescriptors(from.descriptors, to.descriptors, options.correspondences);
  }
  for (const cv::DMatch& m : c.matches) {
    c.toPoints.push_back(to.keypoints[static_cast<size_t>(m.trainIdx)].pt);
    c.toPoints3D.push_back(pointOf(to.points3D, m.trainIdx));
  }
  return c;
}

// Backward estimate (new 3D -> reference keypoints), averaged with the forward one: errors of
// the two directions come from different depth measurements and partly cancel.
Transform averageWithBackward(const Transform& forward, const VisualFrame& from, const FrameMatches& c,
                              const PnPOptions& pnp) {
  std::vector<cv::Point2f> fromPoints2D;
  for (const cv::DMatch& m : c.matches) fromPoints2D.push_back(from.keypoints[static_cast<size_t>(m.queryIdx)].pt);
  const MotionEstimate backward = estimateMotion3DTo2D(c.toPoints3D, fromPoints2D, from.model, pnp);
  return backward.transform.isNull() ? forward : forward.interpolate(0.5, backward.transform.inverse());
}

// Two-view bundle adjustment on the inliers: the reference frame fixed, the new frame and
// (when the reference observed them) the points free. Returns the refined transform, or the
// given one when the adjustment fails.
Transform refineTwoViews(const Transform& transform, const VisualFrame& from, const VisualFrame& to,
                         const FrameMatches& c, const std::vector<cv::Point3f>& fromPoints3D,
                         const std::vector<int>& inliers, double huberPixels) {
  std::map<int, BundleAdjustmentFrame> frames;
  frames[0] = {Transform::Identity(), from.isMap() ? to.model : from.model, true, from.stereoBaseline};
  frames[1] = {transform, to.model, false, to.stereoBaseline};
  std::map<int, cv::Point3f> points;
  std::vector<BundleAdjustmentObservation> observations;
  const bool referenceObserves = !from.isMap() && from.model.isValidForProjection();
  for (int k : inliers) {
    const size_t i = static_cast<size_t>(k);
    points[k] = fromPoints3D[i];
    observations.push_back({1, k, c.toPoints[i], depthInCamera(c.toPoints3D[i], to.model.localTransform())});
    if (referenceObserves) {
      observations.push_back({0, k, from.keypoints[static_cast<size_t>(c.matches[i].queryIdx)].pt,
                              depthInCamera(fromPoints3D[i], from.model.localTransform())});
    }
  }
  BundleAdjustmentOptions ba;
  ba.huberPixels = huberPixels;
  ba.optimizePoints = referenceObserves;
  const BundleAdjustmentSummary s = bundleAdjust(frames, points, observations, ba);
  return s.success ? frames[1].pose : transform;
}

// Mean distance of the inliers from the new camera, and their spread over the new image.
void describeInliers(const Transform& transform, const FrameMatches& c, const std::vector<cv::Point3f>& fromPoints3D,
                     const std::vector<int>& inliers, const VisualFrame& to, RegistrationInfo& info) {
  const Eigen::Isometry3d toFromNew = transform.inverse().toEigen();
  double meanDistance = 0.0;
  int counted = 0;
  for (int k : inliers) {
    const cv::Point3f& p = fromPoints3D[static_cast<size_t>(k)];
    if (!finite3(p)) continue;
    meanDistance += cv::norm(transformPoint(toFromNew, p));
    ++counted;
  }
  info.inliers = static_cast<int>(inliers.size());
  info.inliersMeanDistance = counted > 0 ? meanDistance / counted : 0.0;
  const int cameras = std::max(1, static_cast<int>(to.models.size()));
  const cv::Size imageSize(to.cameraWidth() * cameras, to.model.imageHeight() > 0 ? to.model.imageHeight() : to.grey.rows);
  info.inliersDistribution = inliersDistribution(c.toPoints, inliers, imageSize);
  for (int k : inliers) info.inliersIDs.push_back(info.matchesIDs[static_cast<size_t>(k)]);
}

// Empty when the inliers pass Vis/MeanInliersDistance and Vis/MinInliersDistribution, else why not.
std::string acceptanceProblem(const RegistrationInfo& info, const RegistrationVisOptions& options) {
  std::ostringstream s;
  if (options.meanInliersDistance > 0.0f && info.inliersMeanDistance > options.meanInliersDistance) {
    s << "inliers are " << info.inliersMeanDistance << " m away on average, over Vis/MeanInliersDistance "
      << options.meanInliersDistance << " m";
  } else if (options.minInliersDistribution > 0.0f && info.inliersDistribution < options.minInliersDistribution) {
    s << "inliers spread " << info.inliersDistribution << " over the image, under Vis/MinInliersDistribution "
      << options.minInliersDistribution;
  }
  return s.str();
}

}  // namespace

RegistrationVis::RegistrationVis(const ParametersMap& parameters)
    : RegistrationVis(RegistrationVisOptions::fromParameters(parameters)) {}

RegistrationVis::RegistrationVis(const RegistrationVisOptions& options) : options_(options) {
  std::string why;
  if (!options_.IsValid(&why)) throw ParameterError("visual registration: " + why);
  detector_ = std::make_unique<FeatureDetector>(options_.features);
}

RegistrationVis::~RegistrationVis() = default;

bool RegistrationVis::tracksByOpticalFlow(const VisualFrame& from, const VisualFrame& to) const {
  return options_.correspondences.type == 1 && !from.isMap() && !from.grey.empty() && !to.grey.empty() &&
         from.grey.size() == to.grey.size() &&
         ((!from.severalCameras() && !to.severalCameras()) || from.models.size() == to.models.size());
}

Transform RegistrationVis::computeTransform(const VisualFrame& from, const VisualFrame& to, const Transform& guess,
                                            RegistrationInfo* infoOut, VisualCorrespondences* details) const {
  RegistrationInfo localInfo;
  RegistrationInfo& info = infoOut ? *infoOut : localInfo;
  const Transform first = estimate(from, to, guess, info, details);
  if (first.isNull() || !guess.isNull() || !tracksByOpticalFlow(from, to)) return first;
  // Without a guess, Lucas-Kanade starts each point where it was in the reference image, so only
  // the points that moved less than its pyramid reaches are tracked, and a few of the others
  // converge on a look-alike patch (after a lost frame in OdometryF2F_test's room: 80 inliers of
  // 115 tracks, the pose 8.7 cm off; tracked again from the predicted positions, the whole set).
  RegistrationInfo again;
  VisualCorrespondences againDetails;
  const Transform second = estimate(from, to, first, again, details ? &againDetails : nullptr);
  if (second.isNull() || again.inliers <= info.inliers) return first;
  again.totalTimeMs += info.totalTimeMs;
  info = std::move(again);
  if (details) *details = std::move(againDetails);
  return second;
}

Transform RegistrationVis::estimate(const VisualFrame& from, const VisualFrame& to, const Transform& guess,
                                    RegistrationInfo& info, VisualCorrespondences* details) const {
  const Clock::time_point start = Clock::now();
  info = RegistrationInfo();
  if (details) *details = VisualCorrespondences();
  auto reject = [&](const std::string& why) {
    info.success = false;
    info.rejectedMsg = why;
    info.totalTimeMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return Transform();
  };
  const int minInliers = options_.minInliers;
  if (from.size() == 0) return reject("the reference frame has no features");
  if (to.keypoints.empty()) return reject("the new frame has no features");
  if (!to.model.isValidForProjection()) return reject("the new frame's camera model is not valid for projection");

  // Correspondences.
  const bool flow = tracksByOpticalFlow(from, to);
  const FrameMatches c = flow ? trackByOpticalFlow(from, to, guess, options_) : matchByDescriptors(from, to, guess, options_);
  if (!c.problem.empty()) return reject(c.problem);
  info.matches = static_cast<int>(c.matches.size());
  for (const cv::DMatch& m : c.matches) {
    info.matchesIDs.push_back(from.ids.empty() ? m.queryIdx : from.ids[static_cast<size_t>(m.queryIdx)]);
  }
  if (details) {
    details->matches = c.matches;
    details->toPoints = c.toPoints;
  }
  if (static_cast<int>(c.matches.size()) < std::max(minInliers, 3)) {
    std::ostringstream s;
    s << "only " << c.matches.size() << " " << (flow ? "tracked features" : "feature matches") << ", Vis/MinInliers is "
      << minInliers;
    return reject(s.str());
  }

  // Motion estimation, then the optional backward average and bundle adjustment.
  std::vector<cv::Point3f> fromPoints3D;
  for (const cv::DMatch& m : c.matches) fromPoints3D.push_back(pointOf(from.points3D, m.queryIdx));
  MotionEstimate estimate;
  if (options_.estimationType == 0) {
    estimate = estimateMotion3DTo3D(fromPoints3D, c.toPoints3D, options_.rigid);
  } else if (to.severalCameras()) {
    estimate = estimateMotionMultiCameraPnP(fromPoints3D, c.toPoints, c.toPoints3D, to, options_.pnp, options_.rigid);
  } else {
    estimate = estimateMotion3DTo2D(fromPoints3D, c.toPoints, to.model, options_.pnp);
  }
  if (estimate.transform.isNull()) return reject(estimate.rejectedMsg);
  Transform transform = estimate.transform;
  const std::vector<int>& inliers = estimate.inliers;
  // The backward average and the two-view adjustment know one camera per frame.
  const bool oneCameraEach = !from.severalCameras() && !to.severalCameras();
  if (!options_.forwardEstOnly && oneCameraEach && !from.isMap() && from.model.isValidForProjection()) {
    transform = averageWithBackward(transform, from, c, options_.pnp);
  }
  if (options_.bundleAdjustment == 3 && oneCameraEach) {
    transform = refineTwoViews(transform, from, to, c, fromPoints3D, inliers, options_.pnp.reprojError);
  }
  if (options_.force3DoF) transform = transform.to3DoF();

  // Acceptance.
  describeInliers(transform, c, fromPoints3D, inliers, to, info);
  if (details) details->inliers = inliers;
  const std::string problem = acceptanceProblem(info, options_);
  if (!problem.empty()) return reject(problem);

  // Covariance: from the 3D-3D residuals when the new frame has 3D, else from reprojection.
  int with3D = 0;
  for (int k : inliers) with3D += finite3(c.toPoints3D[static_cast<size_t>(k)]) ? 1 : 0;
  info.covariance = with3D >= 3 ? covarianceFromInliers(fromPoints3D, c.toPoints3D, inliers, transform)
                                : covarianceFromReprojection(fromPoints3D, c.toPoints, inliers, to.model, transform);
  info.success = true;
  info.totalTimeMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return transform;
}

bool RegistrationVis::needsImages() const {
  return options_.correspondences.type == 1 || options_.estimationType == 0 || !options_.forwardEstOnly;
}

namespace {

bool wordsWithoutDescriptors(const Signature& node) {
  return !node.getWords().empty() && node.getWordsDescriptors().empty();
}

}  // namespace

VisualFrame RegistrationVis::frameOf(Signature& node, bool wordsById, std::string* problem) const {
  SensorData& data = node.sensorData();
  // Several cameras: the image tells each camera's width when the models do not.
  const bool needImages =
      needsImages() || data.cameraModels().size() > 1 || data.stereoCameraModels().size() > 1;
  ImageFeatures features;
  std::vector<int> ids;
  if (!node.getWords().empty() && (wordsById || !node.getWordsDescriptors().empty())) {
    features.keypoints = node.getWordsKpts();
    features.points3D = node.getWords3();
    features.descriptors = node.getWordsDescriptors();
    ids = node.wordIdPerKeypoint();
  } else if (!data.keypoints().empty() && !data.descriptors().empty()) {
    features.keypoints = data.keypoints();
    features.points3D = data.keypoints3D();
    features.descriptors = data.descriptors();
  }
  // Raw images, uncompressed in a copy so the node keeps only what it had.
  SensorData raw = data;
  const bool extract = features.empty();
  if ((extract || needImages) && raw.imageRaw().empty() && !raw.imageCompressed().empty()) {
    try {
      raw.uncompress(true, true, false, false);
    } catch (const Error& e) {
      if (problem) *problem = std::string("cannot uncompress the node's images: ") + e.what();
      return VisualFrame();
    }
  }
  if (extract) {
    FeatureExtractionInfo extraction;
    features = detector_->extract(raw, &extraction);
    if (!extraction.problem.empty()) {
      if (problem) *problem = extraction.problem;
      return VisualFrame();
    }
    data.setFeatures(features.keypoints, features.points3D, features.descriptors);
  }
  VisualFrame frame = VisualFrame::fromSensorData(raw, features, options_.features.stereo);
  frame.ids = ids;
  return frame;
}

Transform RegistrationVis::computeTransform(Signature& from, Signature& to, const Transform& guess,
                                            RegistrationInfo* info) const {
  std::string problem;
  const bool wordsById = !from.getWords().empty() && !to.getWords().empty() &&
                         (wordsWithoutDescriptors(from) || wordsWithoutDescriptors(to));
  const VisualFrame a = frameOf(from, wordsById, &problem);
  if (!problem.empty()) {
    if (info) {
      *info = RegistrationInfo();
      info->rejectedMsg = "node " + std::to_string(from.id()) + ": " + problem;
    }
    return Transform();
  }
  const VisualFrame b = frameOf(to, wordsById, &problem);
  if (!problem.empty()) {
    if (info) {
      *info = RegistrationInfo();
      info->rejectedMsg = "node " + std::to_string(to.id()) + ": " + problem;
    }
    return Transform();
  }
  try {
    return computeTransform(a, b, guess, info);
  } catch (const cv::Exception& e) {
    if (info) info->rejectedMsg = std::string("OpenCV error during visual registration: ") + e.what();
  } catch (const std::invalid_argument& e) {
    if (info) info->rejectedMsg = e.what();
  }
  return Transform();
}

}  // namespace rtabmap

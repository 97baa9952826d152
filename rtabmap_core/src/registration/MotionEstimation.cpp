#include "rtabmap_core/registration/MotionEstimation.h"

#include "rtabmap_core/registration/RegistrationVis.h"
#include "MultiCameraReprojection.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <sstream>

namespace rtabmap {
namespace {

bool finite3(const cv::Point3f& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }
bool finite2(const cv::Point2f& p) { return std::isfinite(p.x) && std::isfinite(p.y); }

std::string tooFew(int have, const std::string& what, int minInliers) {
  std::ostringstream s;
  s << "only " << have << " " << what << ", Vis/MinInliers is " << minInliers;
  return s.str();
}

Transform fromRvecTvec(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d r;
  cv::cv2eigen(R, r);
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = r;
  iso.translation() = Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  return Transform(iso).inverse();
}

bool finiteMat(const cv::Mat& m) { return cv::checkRange(m); }

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(mid), v.end());
  return v[mid];
}

// 1.4826 x median: the standard deviation of a zero-mean Gaussian from the median of the
// absolute values of its samples.
constexpr double kMadToSigma = 1.4826;
constexpr double kMinVariance = 1e-6;

Eigen::Matrix<double, 6, 6> diagonalCovariance(double linearVariance, double angularVariance) {
  Eigen::Matrix<double, 6, 6> c = Eigen::Matrix<double, 6, 6>::Zero();
  for (int i = 0; i < 3; ++i) c(i, i) = std::max(kMinVariance, linearVariance);
  for (int i = 3; i < 6; ++i) c(i, i) = std::max(kMinVariance, angularVariance);
  return c;
}

}  // namespace

bool PnPOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (!(reprojError > 0.0f)) return fail("Vis/PnPReprojError must be positive");
  if (iterations < 1) return fail("Vis/Iterations must be at least 1");
  if (flags < 0 || flags > 2) return fail("Vis/PnPFlags must be 0 (iterative), 1 (EPnP) or 2 (P3P)");
  if (refineIterations < 0) return fail("Vis/PnPRefineIterations must not be negative");
  if (shuffleSeed < 0) return fail("Vis/PnPShuffleSeed must not be negative");
  if (minInliers < 0) return fail("Vis/MinInliers must not be negative");
  return true;
}

bool RigidOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (!(inlierDistance > 0.0f)) return fail("Vis/InlierDistance must be positive");
  if (iterations < 1) return fail("Vis/Iterations must be at least 1");
  if (refineIterations < 0) return fail("Vis/RefineIterations must not be negative");
  if (minInliers < 0) return fail("Vis/MinInliers must not be negative");
  return true;
}

MotionEstimate estimateMotion3DTo2D(const std::vector<cv::Point3f>& objectPoints,
                                    const std::vector<cv::Point2f>& imagePoints, const CameraModel& model,
                                    const PnPOptions& options) {
  MotionEstimate result;
  if (objectPoints.size() != imagePoints.size()) {
    result.rejectedMsg = "PnP: as many 3D points as 2D points expected";
    return result;
  }
  if (!model.isValidForProjection()) {
    result.rejectedMsg = "PnP: camera model not valid for projection";
    return result;
  }
  std::vector<cv::Point3f> obj;
  std::vector<cv::Point2f> img;
  std::vector<int> index;
  for (size_t i = 0; i < objectPoints.size(); ++i) {
    if (finite3(objectPoints[i]) && finite2(imagePoints[i])) {
      obj.push_back(objectPoints[i]);
      img.push_back(imagePoints[i]);
      index.push_back(static_cast<int>(i));
    }
  }
  // OpenCV's RANSAC seeds its generator with a constant: the draw depends on the input order
  // only. A seed permutes that order, for another draw just as reproducible (the 7-Scenes ATE moves
  // by +-0.3 cm from one draw to the next: single runs do not compare variants).
  if (options.shuffleSeed > 0) {
    std::vector<size_t> order(obj.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::shuffle(order.begin(), order.end(), std::mt19937(static_cast<uint32_t>(options.shuffleSeed)));
    std::vector<cv::Point3f> o(obj.size());
    std::vector<cv::Point2f> p(obj.size());
    std::vector<int> x(obj.size());
    for (size_t i = 0; i < order.size(); ++i) {
      o[i] = obj[order[i]];
      p[i] = img[order[i]];
      x[i] = index[order[i]];
    }
    obj.swap(o);
    img.swap(p);
    index.swap(x);
  }
  // P3P needs 4 points (3 + 1 to disambiguate); the other solvers 4 or more too.
  const int needed = std::max(4, options.minInliers);
  if (static_cast<int>(obj.size()) < needed) {
    result.rejectedMsg = tooFew(static_cast<int>(obj.size()), "correspondences with a 3D point", options.minInliers);
    return result;
  }
  const cv::Mat K = model.K();
  const Transform local = model.localTransform();
  // No extrinsic guess: the RANSAC kernel (EPnP, or P3P) ignores it, and with one OpenCV starts
  // its final Levenberg-Marquardt pass on the consensus set from the guess's buffer, which each
  // kernel run has overwritten: from the last hypothesis, not the best (a wrong pose for 6 of
  // the 20 draws in MotionEstimation_test). Without it, from the best model.
  cv::Mat rvec, tvec;
  const int flag = options.flags == 1 ? cv::SOLVEPNP_EPNP : options.flags == 2 ? cv::SOLVEPNP_P3P : cv::SOLVEPNP_ITERATIVE;
  std::vector<int> inliers;
  bool ok = false;
  try {
    ok = cv::solvePnPRansac(obj, img, K, cv::noArray(), rvec, tvec, false, options.iterations, options.reprojError,
                            0.99, inliers, flag);
  } catch (const cv::Exception& e) {
    result.rejectedMsg = std::string("PnP RANSAC failed: ") + e.what();
    return result;
  }
  if (!ok || !finiteMat(rvec) || !finiteMat(tvec)) {
    result.rejectedMsg = "PnP RANSAC found no consistent pose among " + std::to_string(obj.size()) + " correspondences";
    return result;
  }
  // The correspondences within the reprojection error under a pose, in front of the camera;
  // `projected` keeps the last call's projections (the inlier RMSE below reads them). A pinhole
  // projects a point behind the camera too (x/z is unchanged when x and z change sign), so
  // without the depth test a pose that puts a near-planar scene behind the camera, turned about
  // half a turn, can count the same inliers as the true one (a 3 m, 180 degree error accepted
  // in RegistrationVis_test's room with other textures).
  const float thr2 = options.reprojError * options.reprojError;
  std::vector<cv::Point2f> projected;
  auto inliersUnder = [&](const cv::Mat& r, const cv::Mat& t, std::vector<int>& out) {
    cv::projectPoints(obj, r, t, K, cv::noArray(), projected);
    cv::Matx33d R;
    cv::Rodrigues(r, R);
    cv::Mat_<double> tz;
    t.convertTo(tz, CV_64F);
    out.clear();
    for (size_t i = 0; i < obj.size(); ++i) {
      const cv::Point2f d = projected[i] - img[i];
      const cv::Point3f& X = obj[i];
      const double depth = R(2, 0) * X.x + R(2, 1) * X.y + R(2, 2) * X.z + tz(2);
      if (d.dot(d) <= thr2 && depth > 0.0) out.push_back(static_cast<int>(i));
    }
  };
  auto subset = [&](const std::vector<int>& ids, std::vector<cv::Point3f>& o, std::vector<cv::Point2f>& p) {
    o.clear();
    p.clear();
    for (int i : ids) {
      o.push_back(obj[static_cast<size_t>(i)]);
      p.push_back(img[static_cast<size_t>(i)]);
    }
  };
  // Levenberg-Marquardt can also leave the basin from the best model (OpenCV's final pass did on
  // OdometryF2M_test's sequence: 161 RANSAC inliers, none under its pose, 6.8 m off). A pose that
  // keeps less than half the inliers it started from is a divergence, not a refinement.
  auto diverged = [](size_t kept, size_t from) { return kept < from / 2; };
  std::vector<cv::Point3f> o;
  std::vector<cv::Point2f> p;
  std::vector<int> current, kept;  // current: the inliers under (rvec, tvec)
  inliersUnder(rvec, tvec, current);
  if (diverged(current.size(), inliers.size()) && inliers.size() >= 4) {
    subset(inliers, o, p);  // RANSAC's consensus set: EPnP on it, in closed form
    cv::Mat r, t;
    if (cv::solvePnP(o, p, K, cv::noArray(), r, t, false, cv::SOLVEPNP_EPNP) && finiteMat(r) && finiteMat(t)) {
      rvec = r;
      tvec = t;
      inliersUnder(rvec, tvec, current);
    }
  }
  // Refinement: re-select the inliers of the whole set under the current pose and solve again
  // on them, so the final pose uses every correspondence consistent with it, not only those
  // of the best minimal sample.
  for (int it = 0; it < options.refineIterations && current.size() >= 4; ++it) {
    subset(current, o, p);
    cv::Mat r = rvec.clone(), t = tvec.clone();
    if (!cv::solvePnP(o, p, K, cv::noArray(), r, t, true, cv::SOLVEPNP_ITERATIVE) || !finiteMat(r) || !finiteMat(t)) break;
    inliersUnder(r, t, kept);
    if (diverged(kept.size(), current.size())) {
      inliersUnder(rvec, tvec, current);  // back to the pose kept (and its projections)
      break;
    }
    rvec = r;
    tvec = t;
    current.swap(kept);
  }
  inliers.swap(current);
  if (static_cast<int>(inliers.size()) < options.minInliers || inliers.size() < 4) {
    result.rejectedMsg = tooFew(static_cast<int>(inliers.size()), "inliers after PnP RANSAC", options.minInliers);
    return result;
  }
  double sum = 0.0;
  for (int i : inliers) {
    const cv::Point2f d = projected[static_cast<size_t>(i)] - img[static_cast<size_t>(i)];
    sum += d.dot(d);
  }
  result.inlierRmse = std::sqrt(sum / static_cast<double>(inliers.size()));
  for (int i : inliers) result.inliers.push_back(index[static_cast<size_t>(i)]);
  std::sort(result.inliers.begin(), result.inliers.end());  // in the caller's order, shuffled or not
  result.transform = fromRvecTvec(rvec, tvec) * local.inverse();
  return result;
}

Transform rigidTransform3D(const std::vector<Eigen::Vector3d>& reference, const std::vector<Eigen::Vector3d>& moved) {
  if (reference.size() != moved.size() || reference.size() < 3) return Transform();
  Eigen::Matrix3Xd src(3, static_cast<long>(moved.size())), dst(3, static_cast<long>(reference.size()));
  for (size_t i = 0; i < moved.size(); ++i) {
    src.col(static_cast<long>(i)) = moved[i];
    dst.col(static_cast<long>(i)) = reference[i];
  }
  // Collinear (or coincident) points leave the rotation about their line undetermined.
  const Eigen::Vector3d mean = src.rowwise().mean();
  const Eigen::Matrix3d cov = (src.colwise() - mean) * (src.colwise() - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  if (eig.eigenvalues()(1) < 1e-12 * std::max(1.0, eig.eigenvalues()(2))) return Transform();
  const Eigen::Matrix4d m = Eigen::umeyama(src, dst, false);
  if (!m.allFinite()) return Transform();
  return Transform(m);
}

MotionEstimate estimateMotion3DTo3D(const std::vector<cv::Point3f>& referencePoints,
                                    const std::vector<cv::Point3f>& newPoints, const RigidOptions& options) {
  MotionEstimate result;
  if (referencePoints.size() != newPoints.size()) {
    result.rejectedMsg = "3D-3D: as many reference points as new points expected";
    return result;
  }
  std::vector<Eigen::Vector3d> ref, mov;
  std::vector<int> index;
  for (size_t i = 0; i < referencePoints.size(); ++i) {
    if (finite3(referencePoints[i]) && finite3(newPoints[i])) {
      ref.emplace_back(referencePoints[i].x, referencePoints[i].y, referencePoints[i].z);
      mov.emplace_back(newPoints[i].x, newPoints[i].y, newPoints[i].z);
      index.push_back(static_cast<int>(i));
    }
  }
  const int n = static_cast<int>(ref.size());
  if (n < std::max(3, options.minInliers)) {
    result.rejectedMsg = tooFew(n, "correspondences with 3D points on both sides", options.minInliers);
    return result;
  }
  const double thr2 = static_cast<double>(options.inlierDistance) * options.inlierDistance;
  auto inliersOf = [&](const Transform& T, std::vector<int>& out) {
    out.clear();
    const Eigen::Isometry3d& iso = T.toEigen();
    for (int i = 0; i < n; ++i) {
      if ((ref[static_cast<size_t>(i)] - iso * mov[static_cast<size_t>(i)]).squaredNorm() <= thr2) out.push_back(i);
    }
  };
  std::mt19937 rng(20190101u);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::vector<int> best, current;
  Transform bestT;
  int maxIterations = options.iterations;
  for (int it = 0; it < maxIterations; ++it) {
    int a = pick(rng), b = pick(rng), c = pick(rng);
    if (a == b || a == c || b == c) continue;
    const Transform T = rigidTransform3D({ref[static_cast<size_t>(a)], ref[static_cast<size_t>(b)], ref[static_cast<size_t>(c)]},
                                         {mov[static_cast<size_t>(a)], mov[static_cast<size_t>(b)], mov[static_cast<size_t>(c)]});
    if (T.isNull()) continue;
    inliersOf(T, current);
    if (current.size() > best.size()) {
      best.swap(current);
      bestT = T;
      // Adaptive stop: enough samples to have drawn an all-inlier triple with 99% confidence.
      const double w = static_cast<double>(best.size()) / n;
      const double p = 1.0 - w * w * w;
      if (p <= 0.0) break;
      const double needed = std::log(0.01) / std::log(p);
      if (needed < maxIterations) maxIterations = std::max(it + 1, static_cast<int>(std::ceil(needed)));
    }
  }
  if (bestT.isNull()) {
    result.rejectedMsg = "3D-3D RANSAC found no non-degenerate sample among " + std::to_string(n) + " correspondences";
    return result;
  }
  for (int it = 0; it < options.refineIterations; ++it) {
    std::vector<Eigen::Vector3d> r, m;
    for (int i : best) {
      r.push_back(ref[static_cast<size_t>(i)]);
      m.push_back(mov[static_cast<size_t>(i)]);
    }
    const Transform T = rigidTransform3D(r, m);
    if (T.isNull()) break;
    inliersOf(T, current);
    if (current.size() < best.size() && it > 0) break;  // refinement made it worse: stop
    bestT = T;
    best.swap(current);
  }
  if (static_cast<int>(best.size()) < std::max(3, options.minInliers)) {
    result.rejectedMsg = tooFew(static_cast<int>(best.size()), "inliers after 3D-3D RANSAC", options.minInliers);
    return result;
  }
  double sum = 0.0;
  for (int i : best) sum += (ref[static_cast<size_t>(i)] - bestT.toEigen() * mov[static_cast<size_t>(i)]).squaredNorm();
  result.inlierRmse = std::sqrt(sum / static_cast<double>(best.size()));
  for (int i : best) result.inliers.push_back(index[static_cast<size_t>(i)]);
  result.transform = bestT;
  return result;
}

Eigen::Matrix<double, 6, 6> covarianceFromInliers(const std::vector<cv::Point3f>& referencePoints,
                                                  const std::vector<cv::Point3f>& newPoints,
                                                  const std::vector<int>& inliers, const Transform& transform) {
  std::vector<double> distances, angles;
  if (transform.isNull()) return Eigen::Matrix<double, 6, 6>::Identity();
  const Eigen::Isometry3d& T = transform.toEigen();
  for (int i : inliers) {
    if (i < 0 || static_cast<size_t>(i) >= referencePoints.size() || static_cast<size_t>(i) >= newPoints.size()) continue;
    const cv::Point3f& a = referencePoints[static_cast<size_t>(i)];
    const cv::Point3f& b = newPoints[static_cast<size_t>(i)];
    if (!finite3(a) || !finite3(b)) continue;
    const Eigen::Vector3d r(a.x, a.y, a.z);
    const Eigen::Vector3d m = T * Eigen::Vector3d(b.x, b.y, b.z);
    distances.push_back((r - m).norm());
    if (r.norm() > 0.0 && m.norm() > 0.0) {
      const double c = std::clamp(r.normalized().dot(m.normalized()), -1.0, 1.0);
      angles.push_back(std::acos(c));
    }
  }
  if (distances.size() < 3) return Eigen::Matrix<double, 6, 6>::Identity();
  const double sigmaLinear = kMadToSigma * median(distances);
  const double sigmaAngular = kMadToSigma * median(angles);
  return diagonalCovariance(sigmaLinear * sigmaLinear, sigmaAngular * sigmaAngular);
}

Eigen::Matrix<double, 6, 6> covarianceFromReprojection(const std::vector<cv::Point3f>& objectPoints,
                                                       const std::vector<cv::Point2f>& imagePoints,
                                                       const std::vector<int>& inliers, const CameraModel& model,
                                                       const Transform& transform) {
  if (transform.isNull() || !model.isValidForProjection()) return Eigen::Matrix<double, 6, 6>::Identity();
  const Eigen::Isometry3d worldToCamera = (transform * model.localTransform()).inverse().toEigen();
  const double f = model.fx();
  std::vector<double> metric, angular;
  for (int i : inliers) {
    if (i < 0 || static_cast<size_t>(i) >= objectPoints.size() || static_cast<size_t>(i) >= imagePoints.size()) continue;
    const cv::Point3f& o = objectPoints[static_cast<size_t>(i)];
    if (!finite3(o)) continue;
    const Eigen::Vector3d c = worldToCamera * Eigen::Vector3d(o.x, o.y, o.z);
    double u, v;
    if (!model.reproject(c.x(), c.y(), c.z(), u, v)) continue;
    const double e = std::hypot(u - imagePoints[static_cast<size_t>(i)].x, v - imagePoints[static_cast<size_t>(i)].y);
    metric.push_back(e * c.z() / f);
    angular.push_back(e / f);
  }
  if (metric.size() < 3) return Eigen::Matrix<double, 6, 6>::Identity();
  const double sigmaLinear = kMadToSigma * median(metric);
  const double sigmaAngular = kMadToSigma * median(angular);
  return diagonalCovariance(sigmaLinear * sigmaLinear, sigmaAngular * sigmaAngular);
}

// ---- Multi-camera PnP ---------------------------------------------------------------------------

namespace {

using registration_internal::CameraObservation;
using registration_internal::PinholeCamera;

// Reprojection residual (pixels) of an observation under the new base pose T; false when the
// point is behind its camera.
bool reprojectionResidual(const Eigen::Isometry3d& T, const CameraObservation& o, const std::vector<PinholeCamera>& cams,
                          Eigen::Vector2d& r) {
  const PinholeCamera& c = cams[static_cast<size_t>(o.camera)];
  const Eigen::Vector3d q = c.opticalFromBase * (T.inverse() * o.point);
  if (q.z() <= 1e-6) return false;
  r = Eigen::Vector2d(c.fx * q.x() / q.z() + c.cx, c.fy * q.y() / q.z() + c.cy) - o.pixel;
  return true;
}

std::vector<int> reprojectionInliers(const Eigen::Isometry3d& T, const std::vector<CameraObservation>& obs,
                                     const std::vector<PinholeCamera>& cams, double maxError, double* rmse) {
  std::vector<int> inliers;
  double sum = 0.0;
  Eigen::Vector2d r;
  for (size_t i = 0; i < obs.size(); ++i) {
    if (!reprojectionResidual(T, obs[i], cams, r) || r.norm() > maxError) continue;
    inliers.push_back(static_cast<int>(i));
    sum += r.squaredNorm();
  }
  if (rmse) *rmse = inliers.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(inliers.size()));
  return inliers;
}

}  // namespace

MotionEstimate estimateMotionMultiCameraPnP(const std::vector<cv::Point3f>& objectPoints,
                                            const std::vector<cv::Point2f>& imagePoints,
                                            const std::vector<cv::Point3f>& newPoints3D, const VisualFrame& to,
                                            const PnPOptions& pnp, const RigidOptions& rigid) {
  MotionEstimate result;
  if (objectPoints.size() != imagePoints.size() || newPoints3D.size() != imagePoints.size()) {
    result.rejectedMsg = "multi-camera PnP: one 3D point, pixel and new 3D point per correspondence expected";
    return result;
  }
  std::vector<PinholeCamera> cams;
  for (const CameraModel& m : to.models) {
    if (!m.isValidForProjection()) {
      result.rejectedMsg = "multi-camera PnP: a camera model is not valid for projection";
      return result;
    }
    cams.push_back({m.localTransform().inverse().toEigen(), m.fx(), m.fy(), m.cx(), m.cy()});
  }
  std::vector<CameraObservation> obs;
  std::vector<int> index;
  const int w = to.cameraWidth();
  for (size_t i = 0; i < objectPoints.size(); ++i) {
    if (!finite3(objectPoints[i]) || !finite2(imagePoints[i])) continue;
    CameraObservation o;
    o.point = Eigen::Vector3d(objectPoints[i].x, objectPoints[i].y, objectPoints[i].z);
    o.camera = to.cameraOf(imagePoints[i].x);
    o.pixel = Eigen::Vector2d(imagePoints[i].x - static_cast<double>(o.camera) * w, imagePoints[i].y);
    obs.push_back(o);
    index.push_back(static_cast<int>(i));
  }
  if (static_cast<int>(obs.size()) < std::max(4, pnp.minInliers)) {
    result.rejectedMsg = "multi-camera PnP: " + tooFew(static_cast<int>(obs.size()), "correspondences with a 3D point", pnp.minInliers);
    return result;
  }
  // First hypothesis: the 3D->3D estimate from the new frame's own depth.
  const MotionEstimate start = estimateMotion3DTo3D(objectPoints, newPoints3D, rigid);
  if (start.transform.isNull()) {
    result.rejectedMsg = "multi-camera PnP needs a 3D->3D first estimate, which failed: " + start.rejectedMsg;
    return result;
  }
  // Its 3D inliers start the refinement: a few pixels of depth noise may put their
  // reprojections just over Vis/PnPReprojError before it.
  Eigen::Isometry3d T = start.transform.toEigen();
  std::vector<int> inliers;
  for (int i : start.inliers) {
    const auto it = std::lower_bound(index.begin(), index.end(), i);
    if (it != index.end() && *it == i) inliers.push_back(static_cast<int>(it - index.begin()));
  }
  for (int it = 0; it < std::max(1, pnp.refineIterations) + 1 && inliers.size() >= 4; ++it) {
    T = registration_internal::refineMultiCameraReprojection(T, obs, inliers, cams, 10);
    inliers = reprojectionInliers(T, obs, cams, pnp.reprojError, nullptr);
  }
  if (static_cast<int>(inliers.size()) < pnp.minInliers || inliers.size() < 4) {
    result.rejectedMsg = "multi-camera PnP: " + tooFew(static_cast<int>(inliers.size()), "inliers", pnp.minInliers);
    return result;
  }
  reprojectionInliers(T, obs, cams, pnp.reprojError, &result.inlierRmse);
  for (int i : inliers) result.inliers.push_back(index[static_cast<size_t>(i)]);
  result.transform = Transform(T);
  return result;
}

}  // namespace rtabmap

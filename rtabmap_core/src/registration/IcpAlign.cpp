// The ICP itself on prepared clouds: PCL's IterativeClosestPoint with the estimation matching
// the degrees of freedom, then acceptance, the low-complexity strategy and the covariance.
// GCC 12 reports -Warray-bounds inside Eigen's SSE loads of 3-vectors instantiated by PCL's 2D
// estimation and Umeyama: a false positive of its bounds analysis on Eigen's unaligned packet
// loads, in library code we do not control.
#pragma GCC diagnostic ignored "-Warray-bounds"
#include <pcl/common/transforms.h>
#include <pcl/console/print.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/transformation_estimation_2D.h>
#include <pcl/registration/transformation_estimation_point_to_plane_lls.h>

#include <Eigen/Eigenvalues>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "IcpCloud.h"
#include "IcpEstimation.h"

namespace rtabmap::icp {

namespace {

template <typename... Args>
std::string format(const char* fmt, Args... args) {
  char text[256];
  std::snprintf(text, sizeof(text), fmt, args...);
  return text;
}

// The nearest target point of each source point within maxDistance. With minNormalCos > -1
// (3D clouds, both with normals), a pair whose normals point more than its angle apart is
// dropped: a sparse ring lidar samples the floor on rings that move with the robot, so a new
// ring's nearest old point is often the foot of a wall or a corner, whose plane would pull the
// scan sideways or tilt it. Dropping, not searching a farther compatible point: that would
// pair the ring with a point up to a metre away on the floor, equally wrong along it.
pcl::Correspondences findCorrespondences(const IcpCloud& target, const Cloud& sourceInTarget,
                                         float maxDistance, float minNormalCos) {
  pcl::Correspondences pairs;
  pairs.reserve(sourceInTarget.size());
  const float max2 = maxDistance * maxDistance;
  const bool checkNormals = minNormalCos > -1.0f && target.hasNormals && !target.is2d;
  float d2 = 0.0f;
  for (size_t i = 0; i < sourceInTarget.size(); ++i) {
    const Point& p = sourceInTarget[i];
    const int j = target.index.nearest(p.getVector3fMap(), max2, &d2);
    if (j < 0) continue;
    if (checkNormals) {
      const float cosine = p.getNormalVector3fMap().dot((*target.cloud)[j].getNormalVector3fMap());
      // A source point without a normal (zero) has no surface to compare: keep it.
      const bool sourceHasNormal = p.normal_x != 0.0f || p.normal_y != 0.0f || p.normal_z != 0.0f;
      if (sourceHasNormal && cosine < minNormalCos) continue;
    }
    pairs.emplace_back(static_cast<int>(i), j, d2);
  }
  return pairs;
}

// Icp/PointToPlaneMaxNormalAngle as the cosine findCorrespondences compares with (-2: off).
float minNormalCosine(const IcpOptions& options) {
  return options.maxNormalAngle > 0.0f ? std::cos(options.maxNormalAngle) : -2.0f;
}

// PCL's ICP loop with our index as its correspondence search (see IcpScanIndex.h for why).
// Reciprocal correspondences are never enabled here.
class GridCorrespondenceEstimation : public pcl::registration::CorrespondenceEstimationBase<Point, Point, float> {
 public:
  GridCorrespondenceEstimation(const IcpCloud* target, float minNormalCos)
      : target_(target), minNormalCos_(minNormalCos) {
    corr_name_ = "GridCorrespondenceEstimation";
  }
  void determineCorrespondences(pcl::Correspondences& correspondences, double maxDistance) override {
    correspondences = findCorrespondences(*target_, *input_, static_cast<float>(maxDistance), minNormalCos_);
  }
  void determineReciprocalCorrespondences(pcl::Correspondences& correspondences, double maxDistance) override {
    determineCorrespondences(correspondences, maxDistance);
  }
  pcl::registration::CorrespondenceEstimationBase<Point, Point, float>::Ptr clone() const override {
    return std::make_shared<GridCorrespondenceEstimation>(*this);
  }

 private:
  const IcpCloud* target_;
  float minNormalCos_;
};

// Spread of the source points: smallest over largest eigenvalue of their covariance (in the
// plane for 2D), 0 for points on a line, 1 for an even spread.
double pointDistribution(const Cloud& cloud, bool is2d) {
  if (cloud.size() < 3) return 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Point& p : cloud) mean += p.getVector3fMap().cast<double>();
  mean /= static_cast<double>(cloud.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Point& p : cloud) {
    const Eigen::Vector3d d = p.getVector3fMap().cast<double>() - mean;
    cov += d * d.transpose();
  }
  if (is2d) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(cov.topLeftCorner<2, 2>());
    const auto v = solver.eigenvalues();
    return v(1) > 0.0 ? std::max(0.0, v(0)) / v(1) : 0.0;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  const auto v = solver.eigenvalues();
  return v(2) > 0.0 ? std::max(0.0, v(0)) / v(2) : 0.0;
}

// Covariance of (x y z roll pitch yaw) from the residuals: sigma^2 (J^T J / n)^-1 over the
// estimated degrees of freedom, sigma^2 the residual variance. Dividing J^T J by n on purpose
// reports the uncertainty of a single point's worth of evidence rather than the
// (J^T J)^-1 of n independent points: scan residuals are correlated (the same wall, the same
// range bias), so that one would claim millimetre odometry links and no loop closure could
// ever correct them in the graph. A direction the surfaces do not constrain (an information
// eigenvalue near 0) gets a variance capped at 1 (m^2 or rad^2): nothing is known there.
// Degrees of freedom not estimated (z, roll, pitch of a planar scan) are fixed by the model and
// get the smallest variance of the estimated ones, so the matrix stays invertible.
Eigen::Matrix<double, 6, 6> residualCovariance(const AlignmentInformation& alignment, const DofMask& dofs) {
  constexpr double kMinVariance = 1e-6;  // (1 mm)^2: perfect synthetic data must not give 0
  constexpr double kMaxVariance = 1.0;
  const double sigma2 = std::max(alignment.residualVariance, kMinVariance);
  int index[6];
  int n = 0;
  for (int i = 0; i < 6; ++i) {
    if (dofs[i]) index[n++] = i;
  }
  Eigen::MatrixXd info(n, n);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) info(r, c) = alignment.normalisedInformation(index[r], index[c]);
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(info);
  Eigen::VectorXd variances(n);
  for (int i = 0; i < n; ++i) {
    const double lambda = solver.eigenvalues()(i);
    variances(i) = lambda > sigma2 / kMaxVariance ? sigma2 / lambda : kMaxVariance;
  }
  const Eigen::MatrixXd sub = solver.eigenvectors() * variances.asDiagonal() * solver.eigenvectors().transpose();
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  double smallest = kMaxVariance;
  for (int r = 0; r < n; ++r) {
    smallest = std::min(smallest, sub(r, r));
    for (int c = 0; c < n; ++c) covariance(index[r], index[c]) = sub(r, c);
  }
  for (int i = 0; i < 6; ++i) {
    if (!dofs[i]) covariance(i, i) = std::max(smallest, kMinVariance);
  }
  return covariance;
}

// Low-complexity strategy 1: keep the ICP rotation and the ICP translation along the directions
// the normals constrain; along the others (the corridor's axis) keep the guess's translation.
Transform keepGuessAlongUnconstrained(const Transform& result, const Transform& guess,
                                      const StructuralComplexity& complexity, float minComplexity) {
  Eigen::Matrix3d projector = Eigen::Matrix3d::Zero();
  for (int i = 0; i < complexity.dimensions; ++i) {
    if (complexity.relativeEigenvalue(i) >= minComplexity) {
      const Eigen::Vector3d v = complexity.directions.col(i);
      projector += v * v.transpose();
    }
  }
  Eigen::Isometry3d out = result.toEigen();
  const Eigen::Vector3d tg = guess.translation();
  out.translation() = tg + projector * (result.translation() - tg);
  return Transform(out);
}

}  // namespace

Transform registerClouds(const IcpCloud& target, const IcpCloud& source, const Transform& guessIn,
                         const IcpOptions& options, RegistrationInfo* infoOut) {
  const auto start = std::chrono::steady_clock::now();
  RegistrationInfo scratch;
  RegistrationInfo& info = infoOut ? *infoOut : scratch;
  info.success = false;
  info.rejectedMsg.clear();
  info.icpCorrespondences = 0;
  info.icpInliersRatio = 0.0;
  const auto finish = [&](const Transform& t, const std::string& why) {
    info.success = !t.isNull();
    info.rejectedMsg = why;
    info.totalTimeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return t;
  };

  Transform guess = guessIn.isNull() ? Transform::Identity() : guessIn;
  if (guess.isInvalid()) return finish(Transform(), "the motion guess has NaN or infinite values");
  if (target.size() < 3 || source.size() < 3) {
    return finish(Transform(), "too few points for ICP (" + std::to_string(target.size()) + " and " +
                                   std::to_string(source.size()) + ", at least 3 each)");
  }
  if (target.index.empty() || target.index.maxDistance() < options.maxCorrespondenceDistance) {
    return finish(Transform(), "internal: target cloud not indexed for Icp/MaxCorrespondenceDistance");
  }

  const bool is2d = target.is2d && source.is2d;
  const bool planar = is2d || options.force3DoF;
  // A planar scan carries no z, roll or pitch: a guess with some would tilt it out of its plane.
  if (planar) guess = guess.to3DoF();
  const DofMask dofs = planar ? dofPlanar() : (options.force4DoF ? dof4() : dof6());
  const int dofCount = planar ? 3 : (options.force4DoF ? 4 : 6);
  bool pointToPlane = options.pointToPlane && target.hasNormals;

  // Structural complexity (point-to-plane only: it needs normals on both sides). The lower of
  // the two clouds decides: the target may be a rich map while the scan sees one wall.
  StructuralComplexity complexity;
  bool lowComplexity = false;
  if (pointToPlane && source.hasNormals) {
    const StructuralComplexity ct = cloudComplexity(target);
    const StructuralComplexity cs = cloudComplexity(source, guess.rotationMatrix());
    complexity = cs.value < ct.value ? cs : ct;
    info.icpStructuralComplexity = complexity.value;
    lowComplexity = complexity.value < options.minComplexity;
    if (lowComplexity && options.lowComplexityStrategy == 0) {
      return finish(Transform(), format("structural complexity %.3f < Icp/PointToPlaneMinComplexity %.3f "
                                        "(Icp/PointToPlaneLowComplexityStrategy 0 rejects it)",
                                        complexity.value, options.minComplexity));
    }
    if (lowComplexity && options.lowComplexityStrategy == 2) pointToPlane = false;
  }

  pcl::IterativeClosestPoint<Point, Point, float> icp;
  icp.setInputSource(source.cloud);
  icp.setInputTarget(target.cloud);
  // Correspondences come from the target's index, built by the caller once (an odometry map
  // serves many scans between key frames). The empty kd-tree, marked never to be recomputed,
  // keeps PCL from building one it would not use.
  icp.setCorrespondenceEstimation(std::make_shared<GridCorrespondenceEstimation>(&target, minNormalCosine(options)));
  icp.setSearchMethodTarget(std::make_shared<Tree>(), true);
  icp.setMaxCorrespondenceDistance(options.maxCorrespondenceDistance);
  icp.setMaximumIterations(options.iterations);
  if (options.epsilon > 0.0f) {
    // PCL compares the squared translation step, and the rotation step's cosine.
    icp.setTransformationEpsilon(double(options.epsilon) * options.epsilon);
    icp.setTransformationRotationEpsilon(std::cos(double(options.epsilon)));
  }
  if (pointToPlane && dofCount == 6) {
    icp.setTransformationEstimation(
        std::make_shared<pcl::registration::TransformationEstimationPointToPlaneLLS<Point, Point, float>>());
  } else if (!pointToPlane && is2d) {
    // Closed form in the plane; z stays 0 since every point has z = 0.
    icp.setTransformationEstimation(
        std::make_shared<pcl::registration::TransformationEstimation2D<Point, Point, float>>());
  } else if (pointToPlane || dofCount != 6) {
    icp.setTransformationEstimation(std::make_shared<ConstrainedEstimation>(dofs, pointToPlane));
  }  // else PCL's default: SVD point-to-point over 6 degrees of freedom

  // Without any pair at the guess PCL would print an error and give up: say it ourselves.
  Cloud sourceAtGuess;
  pcl::transformPointCloudWithNormals(*source.cloud, sourceAtGuess, guess.toEigen().matrix().cast<float>());
  if (countCorrespondences(target, sourceAtGuess, options.maxCorrespondenceDistance) < 3) {
    return finish(Transform(), format("the scans do not overlap at the guess: fewer than 3 points within "
                                      "Icp/MaxCorrespondenceDistance %.3f m of the other scan",
                                      options.maxCorrespondenceDistance));
  }

  Cloud aligned;
  {
    // PCL prints "Not enough correspondences found" on stderr when a scan slides out of
    // reach mid-way; we report that ourselves (below). Its verbosity is process-wide: set back
    // right after.
    const pcl::console::VERBOSITY_LEVEL verbosity = pcl::console::getVerbosityLevel();
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    icp.align(aligned, guess.toEigen().matrix().cast<float>());
    pcl::console::setVerbosityLevel(verbosity);
  }
  if (!icp.hasConverged()) {
    return finish(Transform(), format("ICP lost its correspondences (fewer than 3 within "
                                      "Icp/MaxCorrespondenceDistance %.3f m)",
                                      options.maxCorrespondenceDistance));
  }
  Transform result = Transform(Eigen::Matrix4d(icp.getFinalTransformation().cast<double>())).normalized();
  if (planar) result = result.to3DoF();
  if (result.isInvalid()) return finish(Transform(), "ICP diverged (NaN in the transform)");

  // Acceptance on the final alignment.
  Cloud sourceInTarget;
  pcl::transformPointCloudWithNormals(*source.cloud, sourceInTarget, result.toEigen().matrix().cast<float>());
  const pcl::Correspondences pairs =
      findCorrespondences(target, sourceInTarget, options.maxCorrespondenceDistance, minNormalCosine(options));
  info.icpCorrespondences = static_cast<int>(pairs.size());
  info.icpInliersRatio = static_cast<double>(pairs.size()) /
                         std::max(1, std::min(source.expectedPoints, target.expectedPoints));
  info.icpStructuralDistribution = pointDistribution(*source.cloud, is2d);
  const Transform correction = guess.inverse() * result;
  info.icpTranslation = correction.getNorm();
  info.icpRotation = correction.getAngle();
  if (info.icpInliersRatio < options.correspondenceRatio) {
    return finish(Transform(), format("correspondence ratio %.3f < Icp/CorrespondenceRatio %.3f",
                                      info.icpInliersRatio, options.correspondenceRatio));
  }
  if (options.maxTranslation > 0.0f && info.icpTranslation > options.maxTranslation) {
    return finish(Transform(), format("ICP correction of the guess %.3f m > Icp/MaxTranslation %.3f m",
                                      info.icpTranslation, options.maxTranslation));
  }
  if (options.maxRotation > 0.0f && info.icpRotation > options.maxRotation) {
    return finish(Transform(), format("ICP correction of the guess %.3f rad > Icp/MaxRotation %.3f rad",
                                      info.icpRotation, options.maxRotation));
  }

  if (lowComplexity && options.lowComplexityStrategy == 1) {
    // Directions in the target frame: the scan's normals turned by the found rotation, not
    // the guessed one, else a guess off by a few degrees tilts the corridor's axis and lets
    // the lateral correction leak along it.
    const StructuralComplexity ct = cloudComplexity(target);
    const StructuralComplexity cs = cloudComplexity(source, result.rotationMatrix());
    result = keepGuessAlongUnconstrained(result, guess, cs.value < ct.value ? cs : ct, options.minComplexity);
  }

  const AlignmentInformation alignment =
      alignmentInformation(*source.cloud, *target.cloud, pairs, result.toEigen(), pointToPlane, is2d, dofCount);
  info.covariance = residualCovariance(alignment, dofs);
  return finish(result, "");
}

}  // namespace rtabmap::icp

#include "rtabmap_core/registration/BundleAdjustment.h"

#include <ceres/ceres.h>
#include <ceres/manifold.h>

#include <Eigen/Geometry>

#include <cmath>
#include <set>
#include <sstream>

namespace rtabmap {
namespace {

// Reprojection of a world point by a camera-from-world pose (quaternion q in Eigen's x y z w
// order, translation t), with an optional disparity residual when the observation has a depth.
struct ReprojectionCost {
  ReprojectionCost(double u, double v, double fx, double fy, double cx, double cy, double depth, double bf)
      : u(u), v(v), fx(fx), fy(fy), cx(cx), cy(cy), inverseDepth(depth > 0.0 ? 1.0 / depth : 0.0), bf(bf) {}

  template <typename T>
  bool operator()(const T* q, const T* t, const T* X, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> Q(q);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> tt(t);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> P(X);
    const Eigen::Matrix<T, 3, 1> c = Q * P + tt;
    // A point pushed behind the camera by a bad step gets a large but finite residual, so the
    // trust region rejects that step instead of the solver failing on a division by zero.
    const T z = c.z() > T(1e-3) ? c.z() : T(1e-3);
    r[0] = T(fx) * c.x() / z + T(cx) - T(u);
    r[1] = T(fy) * c.y() / z + T(cy) - T(v);
    if (inverseDepth > 0.0) r[2] = T(bf) * (T(1.0) / z - T(inverseDepth));
    return true;
  }

  double u, v, fx, fy, cx, cy, inverseDepth, bf;
};

struct CameraBlock {
  Eigen::Quaterniond q;  // camera from world
  Eigen::Vector3d t;
  double fx, fy, cx, cy;
};

CameraBlock toBlock(const BundleAdjustmentFrame& f) {
  const Eigen::Isometry3d cw = (f.pose * f.model.localTransform()).inverse().toEigen();
  CameraBlock b;
  b.q = Eigen::Quaterniond(cw.rotation()).normalized();
  b.t = cw.translation();
  b.fx = f.model.fx();
  b.fy = f.model.fy();
  b.cx = f.model.cx();
  b.cy = f.model.cy();
  return b;
}

double reprojectionError(const CameraBlock& c, const Eigen::Vector3d& X, const cv::Point2f& uv, bool* inFront) {
  const Eigen::Vector3d p = c.q * X + c.t;
  *inFront = p.z() > 1e-3;
  if (!*inFront) return 0.0;
  return std::hypot(c.fx * p.x() / p.z() + c.cx - uv.x, c.fy * p.y() / p.z() + c.cy - uv.y);
}

}  // namespace

bool BundleAdjustmentOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (iterations < 1) return fail("bundle adjustment needs at least 1 iteration");
  if (!(huberPixels > 0.0)) return fail("the Huber loss scale must be positive");
  if (depthNoise < 0.0) return fail("the depth noise factor must not be negative");
  return true;
}

BundleAdjustmentSummary bundleAdjust(std::map<int, BundleAdjustmentFrame>& frames, std::map<int, cv::Point3f>& points,
                                     const std::vector<BundleAdjustmentObservation>& observations,
                                     const BundleAdjustmentOptions& options) {
  BundleAdjustmentSummary summary;
  std::string why;
  if (!options.IsValid(&why)) {
    summary.message = why;
    return summary;
  }
  std::map<int, CameraBlock> cameras;
  bool anyFixed = false;
  for (const auto& [id, f] : frames) {
    if (f.pose.isNull() || !f.model.isValidForProjection()) {
      summary.message = "frame " + std::to_string(id) + " has no pose or no valid camera model";
      return summary;
    }
    cameras.emplace(id, toBlock(f));
    anyFixed = anyFixed || f.fixed;
  }
  if (!anyFixed) {
    summary.message = "no fixed frame: the solution would float freely (fix at least one frame)";
    return summary;
  }
  std::map<int, Eigen::Vector3d> X;
  for (const auto& [id, p] : points) {
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) X.emplace(id, Eigen::Vector3d(p.x, p.y, p.z));
  }
  // Usable observations, and which points some free frame sees.
  std::vector<size_t> used;
  std::set<int> seenByFree;
  double initial = 0.0;
  for (size_t i = 0; i < observations.size(); ++i) {
    const auto& o = observations[i];
    auto c = cameras.find(o.frame);
    auto x = X.find(o.point);
    if (c == cameras.end() || x == X.end()) continue;
    bool inFront = false;
    const double e = reprojectionError(c->second, x->second, o.uv, &inFront);
    if (!inFront) continue;
    initial += e * e;
    used.push_back(i);
    if (!frames.at(o.frame).fixed) seenByFree.insert(o.point);
  }
  if (used.empty()) {
    summary.message = "no usable observation";
    return summary;
  }
  summary.initialRmsePx = std::sqrt(initial / static_cast<double>(used.size()));

  ceres::Problem problem;
  ceres::Manifold* quaternionManifold = new ceres::EigenQuaternionManifold();
  std::set<int> addedCameras;
  for (size_t i : used) {
    const auto& o = observations[i];
    CameraBlock& c = cameras.at(o.frame);
    Eigen::Vector3d& p = X.at(o.point);
    const BundleAdjustmentFrame& f = frames.at(o.frame);
    // Scale of the depth residual (see the header): disparity for stereo, 1 / k for RGB-D.
    const double bf = f.baseline > 0.0 ? c.fx * f.baseline : (options.depthNoise > 0.0 ? 1.0 / options.depthNoise : 0.0);
    const bool withDepth = o.depth > 0.0f && bf > 0.0;
    ceres::CostFunction* cost;
    if (withDepth) {
      cost = new ceres::AutoDiffCostFunction<ReprojectionCost, 3, 4, 3, 3>(
          new ReprojectionCost(o.uv.x, o.uv.y, c.fx, c.fy, c.cx, c.cy, o.depth, bf));
    } else {
      cost = new ceres::AutoDiffCostFunction<ReprojectionCost, 2, 4, 3, 3>(
          new ReprojectionCost(o.uv.x, o.uv.y, c.fx, c.fy, c.cx, c.cy, 0.0, bf));
    }
    problem.AddResidualBlock(cost, new ceres::HuberLoss(options.huberPixels), c.q.coeffs().data(), c.t.data(), p.data());
    if (addedCameras.insert(o.frame).second) {
      problem.SetManifold(c.q.coeffs().data(), quaternionManifold);
      if (f.fixed) {
        problem.SetParameterBlockConstant(c.q.coeffs().data());
        problem.SetParameterBlockConstant(c.t.data());
      }
    }
  }
  // Ceres takes ownership of the manifold only once it is set on a block.
  if (addedCameras.empty()) delete quaternionManifold;
  for (auto& [id, p] : X) {
    if (!problem.HasParameterBlock(p.data())) continue;
    if (!options.optimizePoints || seenByFree.count(id) == 0) problem.SetParameterBlockConstant(p.data());
  }
  summary.residualBlocks = problem.NumResidualBlocks();

  ceres::Solver::Options solverOptions;
  solverOptions.linear_solver_type = options.optimizePoints ? ceres::DENSE_SCHUR : ceres::DENSE_QR;
  solverOptions.max_num_iterations = options.iterations;
  solverOptions.num_threads = 1;
  solverOptions.logging_type = ceres::SILENT;
  solverOptions.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary ceresSummary;
  ceres::Solve(solverOptions, &problem, &ceresSummary);
  summary.iterations = static_cast<int>(ceresSummary.iterations.size());
  if (!ceresSummary.IsSolutionUsable()) {
    summary.message = "Ceres found no usable solution: " + ceresSummary.message;
    return summary;
  }
  double final = 0.0;
  for (size_t i : used) {
    const auto& o = observations[i];
    bool inFront = false;
    const double e = reprojectionError(cameras.at(o.frame), X.at(o.point), o.uv, &inFront);
    final += e * e;
    if (!inFront || e > 2.0 * options.huberPixels) summary.outliers.push_back(i);
  }
  summary.finalRmsePx = std::sqrt(final / static_cast<double>(used.size()));
  for (auto& [id, f] : frames) {
    if (f.fixed) continue;
    const CameraBlock& c = cameras.at(id);
    Eigen::Isometry3d cw = Eigen::Isometry3d::Identity();
    cw.linear() = c.q.normalized().toRotationMatrix();
    cw.translation() = c.t;
    f.pose = Transform(cw).inverse() * f.model.localTransform().inverse();
  }
  for (auto& [id, p] : points) {
    auto x = X.find(id);
    if (x == X.end()) continue;
    p = cv::Point3f(static_cast<float>(x->second.x()), static_cast<float>(x->second.y()), static_cast<float>(x->second.z()));
  }
  summary.success = true;
  std::ostringstream s;
  s << summary.iterations << " iterations, reprojection RMSE " << summary.initialRmsePx << " -> " << summary.finalRmsePx
    << " px over " << used.size() << " observations";
  summary.message = s.str();
  return summary;
}

}  // namespace rtabmap

#include "CeresGraph.h"

#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/product_manifold.h>
#include <ceres/solver.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <unordered_map>
#include <vector>

#include "GravityResidual.h"
#include "PoseMath.h"
#include "PriorResidual.h"
#include "Se2Residual.h"
#include "Se3Manifold.h"
#include "Se3Residual.h"
#include "rtabmap_core/optimizer/Chi2.h"
#include "rtabmap_core/optimizer/Graph.h"

namespace rtabmap::optimizer_internal {

namespace {

// A residual block kept aside to compute the raw (non-robust) g2o chi2 ourselves.
struct Term {
  const ceres::CostFunction* cost;
  std::vector<const double*> blocks;
};

double chi2Of(const std::vector<Term>& terms) {
  double sum = 0.0;
  double residuals[6];
  for (const Term& term : terms) {
    term.cost->Evaluate(term.blocks.data(), residuals, nullptr);
    const int n = term.cost->num_residuals();
    for (int i = 0; i < n; ++i) sum += residuals[i] * residuals[i];
  }
  return sum;
}

ceres::LossFunction* makeLoss(const OptimizerOptions& options, Link::Type type) {
  if (!options.robust || !graph::isLoopClosureOrProximity(type)) return nullptr;
  if (options.robustLoss == RobustLoss::kHuber) return new ceres::HuberLoss(options.robustWidth);
  return new ceres::CauchyLoss(options.robustWidth);
}

}  // namespace

CeresOutcome solveWithCeres(const OptimizerOptions& options, const SelectedGraph& graph,
                            const std::map<int, Transform>& initial,
                            const std::map<int, Transform>& input) {
  CeresOutcome out;
  const bool is2D = options.force3DoF;
  const int blockSize = is2D ? 3 : 7;

  // Parameter blocks, in increasing id order.
  std::vector<int> ids(graph.nodes.begin(), graph.nodes.end());
  std::unordered_map<int, double*> blockOf;
  std::vector<double> storage(ids.size() * blockSize);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    double* block = storage.data() + k * blockSize;
    const Transform& pose = initial.at(ids[k]);
    if (is2D) {
      block[0] = pose.x();
      block[1] = pose.y();
      block[2] = pose.yaw();
    } else {
      toSE3Block(pose, block);
    }
    blockOf.emplace(ids[k], block);
  }

  // Declared before the problem: destroyed after it.
  std::unique_ptr<ceres::Manifold> manifold;
  if (!is2D) {
    if (options.autoDiff) {
      manifold = std::make_unique<
          ceres::ProductManifold<ceres::EuclideanManifold<3>, ceres::EigenQuaternionManifold>>();
    } else {
      manifold = std::make_unique<Se3TangentManifold>();
    }
  }
  ceres::Problem::Options problemOptions;
  problemOptions.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problemOptions);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    problem.AddParameterBlock(storage.data() + k * blockSize, blockSize, manifold.get());
  }

  std::vector<Term> chi2Terms;
  chi2Terms.reserve(graph.relative.size() + graph.priors.size());
  for (const auto& [key, link] : graph.relative) {
    (void)key;
    double* xi = blockOf.at(link.from());
    double* xj = blockOf.at(link.to());
    ceres::CostFunction* cost = nullptr;
    if (is2D) {
      Eigen::Matrix3d u = Eigen::Matrix3d::Identity();
      if (!options.varianceIgnored &&
          !sqrtInformation<3>(graph::informationSE2(link.infMatrix()), &u)) {
        out.message = "the 3DoF information of " + link.typeName() + " link " +
                      std::to_string(link.from()) + "->" + std::to_string(link.to()) +
                      " is not positive definite";
        return out;
      }
      cost = makeSe2EdgeCost(toSE2(link.transform()), u, options.autoDiff);
    } else {
      Matrix6 u = Matrix6::Identity();
      if (!options.varianceIgnored &&
          !sqrtInformation<6>(graph::informationSE3ToG2o(link.infMatrix()), &u)) {
        out.message = "the information of " + link.typeName() + " link " +
                      std::to_string(link.from()) + "->" + std::to_string(link.to()) +
                      " is not positive definite";
        return out;
      }
      cost = makeSe3EdgeCost(link.transform().translation(),
                             link.transform().quaternion().normalized(), u, options.autoDiff);
    }
    problem.AddResidualBlock(cost, makeLoss(options, link.type()), xi, xj);
    chi2Terms.push_back({cost, {xi, xj}});
  }
  for (const Link& link : graph.priors) {
    double* x = blockOf.at(link.from());
    ceres::CostFunction* cost = nullptr;
    if (is2D) {
      Eigen::Matrix3d u = Eigen::Matrix3d::Identity();
      if (!options.varianceIgnored) sqrtInformation<3>(graph::informationSE2(link.infMatrix()), &u);
      cost = makeSe2PriorCost(toSE2(link.transform()), u, options.autoDiff);
    } else {
      Matrix6 u = Matrix6::Identity();
      if (!options.varianceIgnored) {
        sqrtInformation<6>(graph::informationSE3ToG2o(link.infMatrix()), &u);
      }
      cost = makeSe3PriorCost(link.transform().translation(),
                              link.transform().quaternion().normalized(), u, options.autoDiff);
    }
    problem.AddResidualBlock(cost, nullptr, x);
    chi2Terms.push_back({cost, {x}});
  }
  for (const Link& link : graph.gravity) {
    problem.AddResidualBlock(makeGravityCost(link.transform().quaternion().normalized(),
                                             options.gravitySigma, options.autoDiff),
                             nullptr, blockOf.at(link.from()));
  }
  if (graph.priors.empty()) problem.SetParameterBlockConstant(blockOf.at(graph.root));

  out.initialChi2 = chi2Of(chi2Terms);

  ceres::Solver::Options solverOptions;
  solverOptions.minimizer_type = ceres::TRUST_REGION;
  solverOptions.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solverOptions.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solverOptions.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  solverOptions.max_num_iterations = options.iterations;
  solverOptions.function_tolerance = options.epsilon;
  solverOptions.gradient_tolerance = options.epsilon > 0.0 ? options.gradientTolerance : 0.0;
  solverOptions.parameter_tolerance = options.epsilon > 0.0 ? options.parameterTolerance : 0.0;
  // Start almost as Gauss-Newton (damping 1e-10 of the Jacobi-scaled diagonal): the
  // initialisation puts the graph near the optimum, where Ceres's default radius (1e4) damps
  // steps for several iterations. Slightly damped, not undamped: on parking-garage the pure
  // Gauss-Newton first step from the chordal estimate overshoots. Non-monotonic steps let the
  // solver cross the curved valleys of badly conditioned graphs; Ceres still returns the best
  // parameters met.
  solverOptions.initial_trust_region_radius = 1e10;
  solverOptions.use_nonmonotonic_steps = true;
  solverOptions.num_threads = options.numThreads;
  solverOptions.logging_type = ceres::SILENT;
  solverOptions.minimizer_progress_to_stdout = false;

  std::string error;
  if (!solverOptions.IsValid(&error)) {
    out.message = "invalid solver options: " + error;
    return out;
  }
  ceres::Solver::Summary summary;
  ceres::Solve(solverOptions, &problem, &summary);
  // Ceres's iteration list starts with the evaluation of the initial estimate (iteration 0).
  out.iterations = std::max(0, static_cast<int>(summary.iterations.size()) - 1);
  out.message = summary.message;
  if (summary.termination_type != ceres::CONVERGENCE &&
      summary.termination_type != ceres::NO_CONVERGENCE) {
    out.message = "Ceres failed: " + summary.message;
    return out;
  }
  for (double v : storage) {
    if (!std::isfinite(v)) {
      out.message = "the solution is not finite (" + summary.message + ")";
      return out;
    }
  }
  out.finalChi2 = chi2Of(chi2Terms);
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.success = true;

  for (int id : ids) {
    const double* block = blockOf.at(id);
    if (is2D) {
      const auto in = input.find(id);
      if (in != input.end() && !in->second.isNull()) {
        double x, y, z, roll, pitch, yaw;
        in->second.getTranslationAndEulerAngles(x, y, z, roll, pitch, yaw);
        out.poses.emplace(id, Transform(block[0], block[1], z, roll, pitch, wrapAngle(block[2])));
      } else {
        out.poses.emplace(id, Transform(block[0], block[1], wrapAngle(block[2])));
      }
    } else {
      out.poses.emplace(id, fromSE3Block(block));
    }
  }
  return out;
}

}  // namespace rtabmap::optimizer_internal

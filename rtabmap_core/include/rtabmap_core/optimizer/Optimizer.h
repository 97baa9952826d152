#pragma once
// Pose-graph optimisation (the map correction of RTAB-Map, T-RO 2013 / JFR 2019), on Ceres.
//
// The trio of every solver-like module: OptimizerOptions (from parameters, with IsValid),
// optimizeGraph(), and OptimizerSummary saying what happened in words a user understands.
//
//   OptimizerOptions options = OptimizerOptions::fromParameters(parameters);
//   OptimizerSummary summary;
//   std::map<int, Transform> optimised = optimizeGraph(options, poses, links, &summary);
//   if (!summary.success) RTABMAP_WARN("graph optimisation failed: " << summary.why);
//
// What is optimised (multi-session, Autonomous Robots 2017 / JFR 2019): the graph may hold
// several maps not yet linked together, and links to nodes that are not in `poses` (they are in
// long-term memory). Only the connected component containing the root is optimised; the root
// (by default the most recent node, i.e. the largest non-negative id) stays fixed, so the result
// is expressed in the latest odometry frame and sessions merged by a loop closure end up in one
// referential. Links to nodes absent from `poses` are ignored and counted. Nodes with a null
// input pose are present but without an estimate (e.g. a g2o file made of edges only): the
// initialisation gives them one. Landmark nodes (negative ids, reached by kLandmark links) do
// not need to be in `poses`: they are created and returned with their negative ids.
// Every link is a measurement: a constraint given in both directions counts twice (use
// graph::filterDuplicateLinks on links gathered from both ends, e.g. Signature::getLinks()).
//
// The objective is g2o's: for each link, e' * Omega * e with e = [x, y, theta] of
// Z^-1 * (Xi^-1 * Xj) in 3DoF, and e = [t, qx, qy, qz] (quaternion with w >= 0) in 6DoF, where
// Omega is the link's information with its rotation rows and columns scaled to that
// quaternion-vector error (see optimizer/Chi2.h). So the chi2 the summary reports is the one
// the solver minimises, comparable to g2o's and to the reference values of the data README.
//
// The solver: Ceres Levenberg-Marquardt, sparse normal Cholesky (SuiteSparse CHOLMOD),
// analytic Jacobians (SE3 poses as translation + unit quaternion, increments in the tangent
// space), started almost as Gauss-Newton from the initialisation (initial trust region 1e10,
// non-monotonic steps). With the default chordal initialisation every reference graph of the
// data README reaches its best known chi2 in 2 or 3 steps.
//
// The optimiser never returns non-finite poses: on any failure it returns the input poses
// unchanged and says why in summary.why.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

// How the first estimate of the optimised component is built (Optimizer/Init).
enum class GraphInitialization {
  kInputPoses = 0,    // the poses given; nodes without one composed along links (odometry first)
  kSpanningTree = 1,  // breadth-first spanning tree from the root, composing link transforms
  kChordal = 2,       // chordal relaxation: rotations, then positions, by linear least squares
};
// "input", "tree", "chordal".
const char* initializationName(GraphInitialization init);
// Accepts the names above (and "odometry" for kInputPoses); nullopt otherwise.
std::optional<GraphInitialization> initializationFromName(const std::string& name);

// Robust loss of Optimizer/RobustLoss.
enum class RobustLoss { kCauchy = 0, kHuber = 1 };

struct OptimizerOptions {
  // Optimizer/Iterations: maximum Levenberg-Marquardt iterations.
  int iterations = 20;
  // Optimizer/Epsilon: stop when the relative decrease of the cost is below this (0 = never).
  double epsilon = 1e-6;
  // Optimizer/Init.
  GraphInitialization initialization = GraphInitialization::kChordal;
  // Optimizer/Robust, Optimizer/RobustLoss, Optimizer/RobustWidth: a robust loss on loop-closure,
  // proximity and user links (never on odometry, priors or landmarks). The width is in standard
  // deviations of the link's weighted error.
  bool robust = false;
  RobustLoss robustLoss = RobustLoss::kCauchy;
  double robustWidth = 1.0;
  // Optimizer/PriorsIgnored: ignore kPosePrior links. When priors are used and one lies in the
  // optimised component, the root is not fixed: the priors anchor the graph.
  bool priorsIgnored = true;
  // Optimizer/LandmarksIgnored: ignore kLandmark links (and so the landmarks).
  bool landmarksIgnored = false;
  // Optimizer/VarianceIgnored: identity information for every link.
  bool varianceIgnored = false;
  // Optimizer/GravitySigma: standard deviation (unitless, on the up vector) of kGravity links in
  // 6DoF; 0 = gravity links ignored.
  double gravitySigma = 0.0;
  // Reg/Force3DoF: optimise x, y, yaw only (SE2). Other DoF of the output keep their input value.
  bool force3DoF = false;

  // Not parameters: how the solver runs.
  // Threads Ceres uses to evaluate residuals and Jacobians.
  int numThreads = 1;
  // Automatic instead of analytic derivatives (same residuals; for measurements and tests).
  bool autoDiff = false;
  // Gradient and parameter tolerances of Ceres (stop when the step or the gradient is this small).
  double gradientTolerance = 1e-10;
  double parameterTolerance = 1e-8;

  // Reads the parameters above from a map (missing keys take the declared defaults). Throws
  // ParameterError on an invalid value.
  static OptimizerOptions fromParameters(const ParametersMap& parameters);
  // True if every field is usable; otherwise false and why in *why.
  bool IsValid(std::string* why = nullptr) const;
};

struct OptimizerSummary {
  // The poses returned are the optimised ones (even if the iteration limit was reached).
  bool success = false;
  // Ceres reported convergence (a tolerance was met) before the iteration limit.
  bool converged = false;
  // Failure: what went wrong. Success: how the solver stopped, in words.
  std::string why;

  int rootId = 0;
  bool rootFixed = true;        // false when priors anchor the graph instead
  bool is2D = false;            // optimised as SE2 (Reg/Force3DoF)
  GraphInitialization initialization = GraphInitialization::kChordal;

  // The optimised component.
  int nodes = 0;                // nodes optimised (root and landmarks included)
  int links = 0;                // relative links optimised (priors and gravity not included)
  int priors = 0;               // prior links used
  int gravityLinks = 0;         // gravity links used
  // What was left out.
  // True when the graph had other components (e.g. sessions not yet linked to the root's) or
  // isolated nodes: only the root's component was optimised, and those nodes are not returned.
  bool otherComponentsLeftOut = false;
  int nodesOutsideRootComponent = 0;
  int linksOutsideRootComponent = 0;
  int linksToAbsentNodes = 0;   // an end is neither in `poses` nor a landmark
  int linksIgnoredByOptions = 0;  // priors, landmarks or gravity ignored by the options

  // g2o-convention chi2 (see Chi2.h) over the optimised links and priors, with the weighting
  // used (identity if variance is ignored; before any robust loss). Initial: the estimate the
  // solver started from (after initialisation). -1 when not computed (failure before).
  double initialChi2 = -1.0;
  double finalChi2 = -1.0;
  int iterations = 0;           // Levenberg-Marquardt steps tried (accepted or not)
  // Seconds: initialisation, building and solving the Ceres problem, and in all (whole call).
  double initializationTime = 0.0;
  double solverTime = 0.0;
  double totalTime = 0.0;
};

// Optimises the component of `rootId` (default: the most recent node, the largest id >= 0 among
// the keys of `poses`, or among the ends of the links if no key is >= 0). Returns the optimised poses of that component
// (landmarks included); on failure, returns `poses` unchanged. `summary` may be null.
std::map<int, Transform> optimizeGraph(const OptimizerOptions& options,
                                       const std::map<int, Transform>& poses,
                                       const std::multimap<int, Link>& links,
                                       OptimizerSummary* summary = nullptr,
                                       std::optional<int> rootId = std::nullopt);

// The whole graph of a database (every session): each connected component optimised on its
// own with its oldest node (smallest id) fixed, so maps joined by links share the oldest one's
// referential and a map never linked to another keeps its own. Nodes alone keep their pose.
// Landmark links (to negative ids absent from `poses`) constrain the component of the node that
// saw the landmark; a landmark does not join components. Only nodes are returned.
// `failures` (may be null) gets one line per component whose optimisation failed (its poses
// are then returned as given).
std::map<int, Transform> optimizeEachComponent(const OptimizerOptions& options,
                                               const std::map<int, Transform>& poses,
                                               const std::multimap<int, Link>& links,
                                               std::vector<std::string>* failures = nullptr);

}  // namespace rtabmap

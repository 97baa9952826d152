#pragma once
// The Ceres problem of a selected pose graph, and its solution (internal header).
#include <map>
#include <string>

#include "GraphSelection.h"

namespace rtabmap::optimizer_internal {

struct CeresOutcome {
  bool success = false;    // poses are usable (converged or iteration limit)
  bool converged = false;
  std::string message;     // Ceres's termination message, or why it failed
  int iterations = 0;
  double initialChi2 = -1.0;
  double finalChi2 = -1.0;
  // Optimised poses of the component's nodes. In 2D, z, roll and pitch are those of `input`
  // when the node had an input pose (0 otherwise).
  std::map<int, Transform> poses;
};

// Levenberg-Marquardt with sparse normal Cholesky (SuiteSparse) from `initial` (a pose for
// every node of `graph.nodes`). The root is held constant unless the graph has priors.
CeresOutcome solveWithCeres(const OptimizerOptions& options, const SelectedGraph& graph,
                            const std::map<int, Transform>& initial,
                            const std::map<int, Transform>& input);

}  // namespace rtabmap::optimizer_internal

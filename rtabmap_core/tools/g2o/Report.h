#pragma once
// What rtabmap-g2o prints: the optimisation summary as the --json line, and as text for people.
#include <nlohmann/json.hpp>

#include <ostream>
#include <string>

#include "rtabmap_core/optimizer/GraphIO.h"
#include "rtabmap_core/optimizer/Optimizer.h"

namespace rtabmap::tools::g2o {

struct RunReport {
  std::string input;
  std::string output;           // "" when no output file was asked for
  std::size_t poses = 0;        // nodes of the file
  std::size_t edges = 0;        // links of the file
  bool is2D = false;
  int threads = 1;
  bool autoDiff = false;
  double timeSeconds = 0.0;     // the optimiser call alone (initialisation included), wall clock
  double cpuSeconds = 0.0;      // the same in CPU time of the process (all threads)
  OptimizerSummary summary;
};

// One JSON object: poses, edges, initial_chi2, final_chi2, iterations, time_s, converged, and
// cpu_time_s, success, why, graph ("SE2"/"SE3"), init, root, root_fixed, nodes_optimized, links_optimized,
// links_to_absent_nodes, nodes_outside_root_component, other_components_left_out,
// init_time_s, solver_time_s, threads, jacobians ("analytic"/"autodiff"), input, output.
nlohmann::json toJson(const RunReport& report);

void printText(std::ostream& out, const RunReport& report);

}  // namespace rtabmap::tools::g2o

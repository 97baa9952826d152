#include "g2o/Report.h"

#include <iomanip>

namespace rtabmap::tools::g2o {

nlohmann::json toJson(const RunReport& r) {
  const OptimizerSummary& s = r.summary;
  nlohmann::json j;
  j["input"] = r.input;
  j["output"] = r.output.empty() ? nlohmann::json() : nlohmann::json(r.output);
  j["graph"] = r.is2D ? "SE2" : "SE3";
  j["poses"] = r.poses;
  j["edges"] = r.edges;
  j["success"] = s.success;
  j["converged"] = s.converged;
  j["why"] = s.why;
  j["initial_chi2"] = s.initialChi2;
  j["final_chi2"] = s.finalChi2;
  j["iterations"] = s.iterations;
  j["time_s"] = r.timeSeconds;
  j["cpu_time_s"] = r.cpuSeconds;
  j["init_time_s"] = s.initializationTime;
  j["solver_time_s"] = s.solverTime;
  j["init"] = initializationName(s.initialization);
  j["root"] = s.rootId;
  j["root_fixed"] = s.rootFixed;
  j["nodes_optimized"] = s.nodes;
  j["links_optimized"] = s.links;
  j["links_to_absent_nodes"] = s.linksToAbsentNodes;
  j["nodes_outside_root_component"] = s.nodesOutsideRootComponent;
  j["other_components_left_out"] = s.otherComponentsLeftOut;
  j["threads"] = r.threads;
  j["jacobians"] = r.autoDiff ? "autodiff" : "analytic";
  return j;
}

void printText(std::ostream& out, const RunReport& r) {
  const OptimizerSummary& s = r.summary;
  out << r.input << ": " << (r.is2D ? "SE2" : "SE3") << " graph, " << r.poses << " poses, "
      << r.edges << " edges\n";
  if (!s.success) {
    out << "optimisation FAILED: " << s.why << "\n";
    return;
  }
  out << std::setprecision(6);
  out << "root " << s.rootId << (s.rootFixed ? " (fixed)" : " (free: priors anchor the graph)")
      << ", " << s.nodes << " nodes and " << s.links << " links optimised, initialisation "
      << initializationName(s.initialization) << "\n";
  if (s.otherComponentsLeftOut) {
    out << "left out: " << s.nodesOutsideRootComponent
        << " nodes not connected to the root's component\n";
  }
  if (s.linksToAbsentNodes > 0) {
    out << "ignored: " << s.linksToAbsentNodes << " links to absent nodes\n";
  }
  out << "chi2 " << s.initialChi2 << " -> " << s.finalChi2 << " in " << s.iterations
      << " iterations, " << (s.converged ? "converged" : "not converged") << "\n";
  out << "time " << r.timeSeconds << " s (initialisation " << s.initializationTime
      << " s, Ceres " << s.solverTime << " s; file I/O excluded), CPU " << r.cpuSeconds << " s\n";
  out << s.why << "\n";
  if (!r.output.empty()) out << "written: " << r.output << "\n";
}

}  // namespace rtabmap::tools::g2o

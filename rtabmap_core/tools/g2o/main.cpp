// rtabmap-g2o: optimises a pose graph read from a g2o (or TORO) file with the core's Ceres
// optimiser, reports the chi2 in g2o's convention, and optionally writes the optimised graph.
#include <chrono>
#include <ctime>
#include <iostream>

#include "common/CommandLine.h"
#include "common/Json.h"
#include "g2o/Report.h"
#include "rtabmap_core/optimizer/GraphIO.h"
#include "rtabmap_core/optimizer/Optimizer.h"

namespace {

constexpr int kToolThreads = 1;

}  // namespace

int main(int argc, char** argv) {
  using namespace rtabmap;
  return tools::runTool("rtabmap-g2o", [&] {
    tools::CommandLine cli(
        "rtabmap-g2o",
        "Optimises a pose graph (g2o VERTEX_SE2 / EDGE_SE2 / VERTEX_SE3:QUAT / EDGE_SE3:QUAT, or "
        "TORO .graph) with Levenberg-Marquardt on Ceres (sparse Cholesky), and reports the chi2 "
        "in g2o's convention. Files with edges only are initialised by --init. The root (held "
        "fixed) is the FIX node of the file if any, else the first vertex, as g2o does; only its "
        "connected component is optimised.");
    cli.addPositional("input", "Pose graph to optimise (.g2o, or .graph / .toro for TORO).");
    cli.addPositional("output", "Where to write the optimised graph (format by extension).", false);
    cli.addOption("init", "METHOD",
                  "Initial estimate: chordal (chordal relaxation), tree (breadth-first spanning "
                  "tree) or odometry (the file's vertices; edges-only files compose odometry "
                  "edges). Default: Optimizer/Init (chordal).");
    cli.addOption("iterations", "N",
                  "Maximum Levenberg-Marquardt iterations. Default: Optimizer/Iterations (20).");
    cli.addFlag("robust", "Robust loss (Optimizer/RobustLoss, Optimizer/RobustWidth) on loop "
                          "closures (edges between non-consecutive ids).");
    cli.addOption("root", "ID", "Node held fixed (default: FIX node, else the first vertex).");
    cli.addOption("threads", "N", "Threads for residual evaluation.", std::to_string(kToolThreads));
    cli.addFlag("autodiff", "Automatic instead of analytic Jacobians (for comparisons).");
    cli.addNote("time_s is the optimisation alone (initialisation, Ceres problem and solve), "
                "wall clock; reading and writing files is excluded. cpu_time_s is the same in "
                "process CPU time (all threads): on a loaded machine it is the steadier figure.");
    cli.addNote("Example: rtabmap-g2o --json ../shared/data/posegraphs/intel.g2o /tmp/intel_opt.g2o");
    if (auto exitCode = cli.parse(argc, argv)) return *exitCode;

    const std::string input = cli.positional("input");
    const graph::PoseGraphFile file = graph::readGraph(input);

    OptimizerOptions options = OptimizerOptions::fromParameters(cli.parameters());
    if (file.is2D) options.force3DoF = true;
    if (cli.has("init")) {
      const auto init = initializationFromName(cli.option("init"));
      if (!init) {
        throw tools::UsageError("--init must be chordal, tree or odometry (got '" +
                                cli.option("init") + "')");
      }
      options.initialization = *init;
    }
    if (cli.has("iterations")) options.iterations = cli.optionInt("iterations");
    if (cli.flag("robust")) options.robust = true;
    options.numThreads = cli.optionInt("threads");
    options.autoDiff = cli.flag("autodiff");
    std::string why;
    if (!options.IsValid(&why)) throw tools::UsageError(why);

    std::optional<int> root;
    if (cli.has("root")) {
      root = cli.optionInt("root");
    } else if (!file.fixedIds.empty()) {
      root = file.fixedIds.front();
    } else {
      root = file.poses.begin()->first;
    }

    tools::g2o::RunReport report;
    report.input = input;
    report.output = cli.positional("output");
    report.poses = file.poses.size();
    report.edges = file.links.size();
    report.is2D = options.force3DoF;
    report.threads = options.numThreads;
    report.autoDiff = options.autoDiff;

    const std::clock_t cpuStart = std::clock();
    const auto start = std::chrono::steady_clock::now();
    const std::map<int, Transform> optimized =
        optimizeGraph(options, file.poses, file.links, &report.summary, root);
    report.timeSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report.cpuSeconds = static_cast<double>(std::clock() - cpuStart) / CLOCKS_PER_SEC;

    if (report.summary.success && !report.output.empty()) {
      // Only the optimised component has poses: keep the links between its nodes, so the file
      // written reads back.
      std::multimap<int, Link> links;
      for (const auto& entry : file.links) {
        if (optimized.count(entry.second.from()) && optimized.count(entry.second.to())) {
          links.insert(links.end(), entry);
        }
      }
      graph::writeGraph(report.output, optimized, links, options.force3DoF);
    }
    if (cli.json()) {
      tools::printJsonLine(tools::g2o::toJson(report));
    } else {
      tools::g2o::printText(std::cout, report);
    }
    return report.summary.success ? tools::kExitSuccess : tools::kExitFailure;
  });
}

// optimizeGraph(): selection of the root's component, initialisation, Ceres, and the summary.
#include "rtabmap_core/optimizer/Optimizer.h"

#include <chrono>
#include <sstream>

#include "CeresGraph.h"
#include "GraphSelection.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/optimizer/Graph.h"
#include "rtabmap_core/optimizer/Initialization.h"

namespace rtabmap {

namespace oi = optimizer_internal;

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

std::map<int, Transform> optimizeGraph(const OptimizerOptions& options,
                                       const std::map<int, Transform>& poses,
                                       const std::multimap<int, Link>& links,
                                       OptimizerSummary* summaryOut,
                                       std::optional<int> rootId) {
  const Clock::time_point start = Clock::now();
  OptimizerSummary local;
  OptimizerSummary& summary = summaryOut ? *summaryOut : local;
  summary = OptimizerSummary();
  summary.is2D = options.force3DoF;
  summary.initialization = options.initialization;

  auto fail = [&](const std::string& why) {
    summary.success = false;
    summary.converged = false;
    summary.why = why;
    summary.totalTime = secondsSince(start);
    RTABMAP_WARN("graph optimisation failed: " << why);
    return poses;
  };

  std::string why;
  if (!options.IsValid(&why)) return fail("invalid options: " + why);

  int root = 0;
  if (rootId) {
    root = *rootId;
  } else if (!oi::defaultRoot(poses, links, &root)) {
    return fail("the graph is empty: no node to optimise");
  }
  summary.rootId = root;

  oi::SelectedGraph graph;
  if (!oi::selectGraph(options, poses, links, root, &graph, &summary, &why)) return fail(why);
  summary.rootFixed = graph.priors.empty();

  // Initial estimate.
  const Clock::time_point initStart = Clock::now();
  const auto rootInput = poses.find(root);
  const Transform rootPose = (rootInput != poses.end() && !rootInput->second.isNull())
                                 ? rootInput->second
                                 : Transform::Identity();
  std::map<int, Transform> initial;
  switch (options.initialization) {
    case GraphInitialization::kInputPoses:
      initial = graph::knownPosesInitialization(graph.nodes, poses, options.force3DoF);
      if (initial.empty()) {
        initial = graph::spanningTreeInitialization(root, rootPose, graph.relative, options.force3DoF,
                                                    /*odometryFirst=*/true, &poses);
      }
      break;
    case GraphInitialization::kSpanningTree:
      initial = graph::spanningTreeInitialization(root, rootPose, graph.relative, options.force3DoF);
      break;
    case GraphInitialization::kChordal:
      initial = graph::chordalInitialization(root, rootPose, graph.relative, options.force3DoF,
                                             options.varianceIgnored, &why);
      if (initial.empty()) return fail(why);
      break;
  }
  summary.initializationTime = secondsSince(initStart);
  if (initial.size() != graph.nodes.size()) {
    std::ostringstream s;
    s << "initialisation placed " << initial.size() << " of the " << graph.nodes.size()
      << " nodes of the root's component";
    return fail(s.str());
  }
  for (const auto& [id, pose] : initial) {
    if (pose.isInvalid()) {
      std::ostringstream s;
      s << "initialisation gave node " << id << " a non-finite pose";
      return fail(s.str());
    }
  }

  if (graph.relative.empty() && graph.priors.empty() && graph.gravity.empty()) {
    // A lone root: nothing to optimise.
    summary.success = true;
    summary.converged = true;
    summary.initialChi2 = summary.finalChi2 = 0.0;
    summary.why = "nothing to optimise: the root has no link";
    summary.totalTime = secondsSince(start);
    std::map<int, Transform> out;
    out.emplace(root, rootPose);
    return out;
  }

  const Clock::time_point solveStart = Clock::now();
  oi::CeresOutcome outcome = oi::solveWithCeres(options, graph, initial, poses);
  summary.solverTime = secondsSince(solveStart);
  summary.iterations = outcome.iterations;
  summary.initialChi2 = outcome.initialChi2;
  if (!outcome.success) return fail(outcome.message);
  summary.finalChi2 = outcome.finalChi2;
  summary.converged = outcome.converged;
  summary.success = true;
  summary.why = outcome.converged ? "converged: " + outcome.message
                                  : "stopped at the iteration limit: " + outcome.message;
  summary.totalTime = secondsSince(start);
  return std::move(outcome.poses);
}

std::map<int, Transform> optimizeEachComponent(const OptimizerOptions& options,
                                               const std::map<int, Transform>& poses,
                                               const std::multimap<int, Link>& links,
                                               std::vector<std::string>* failures) {
  std::map<int, Transform> result = poses;
  for (const std::set<int>& component : graph::connectedComponents(poses, links)) {
    if (component.size() < 2) continue;
    std::map<int, Transform> inside;
    for (int id : component) inside.emplace(id, poses.at(id));
    std::multimap<int, Link> insideLinks;
    for (const auto& [from, link] : links) {
      // A landmark's links go with the component of the node that saw it (the optimiser places
      // the landmark); a landmark does not join components.
      const bool landmark = link.type() == Link::kLandmark && link.to() < 0 && !poses.count(link.to());
      if (component.count(link.from()) && (component.count(link.to()) || landmark)) insideLinks.emplace(from, link);
    }
    OptimizerSummary s;
    const std::map<int, Transform> optimised = optimizeGraph(options, inside, insideLinks, &s, *component.begin());
    if (!s.success && failures) {
      failures->push_back("the map of node " + std::to_string(*component.begin()) + " (" +
                          std::to_string(component.size()) + " nodes) was not optimised: " + s.why);
    }
    for (const auto& [id, pose] : optimised) {
      if (result.count(id)) result[id] = pose;
    }
  }
  return result;
}

}  // namespace rtabmap

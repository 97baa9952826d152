#pragma once
// What the optimiser works on (internal header): the links and nodes of the root's connected
// component, once the options, absent nodes and other sessions are taken out.
#include <map>
#include <set>
#include <string>
#include <vector>

#include "rtabmap_core/optimizer/Optimizer.h"

namespace rtabmap::optimizer_internal {

struct SelectedGraph {
  int root = 0;
  std::set<int> nodes;                  // the root's component (landmarks included)
  std::multimap<int, Link> relative;    // relative links inside it
  std::vector<Link> priors;             // prior links on its nodes (if not ignored)
  std::vector<Link> gravity;            // gravity links on its nodes (if used)
};

// The default root: the largest id >= 0 among the keys of `poses`, or if there is none, among
// the ends of `links`. False if there is none at all.
bool defaultRoot(const std::map<int, Transform>& poses, const std::multimap<int, Link>& links,
                 int* root);

// Classifies the links and selects the component of `root`. Fills the counters of `summary`
// (nodes, links, priors, what was left out). False with the reason in *why on invalid input: a
// link that is not valid (Link::isValid), a self-link that is neither a prior nor gravity, a
// root that is not in the graph, a non-finite input pose in the component.
bool selectGraph(const OptimizerOptions& options, const std::map<int, Transform>& poses,
                 const std::multimap<int, Link>& links, int root, SelectedGraph* selected,
                 OptimizerSummary* summary, std::string* why);

}  // namespace rtabmap::optimizer_internal

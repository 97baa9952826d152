#include "GraphSelection.h"

#include <Eigen/Cholesky>

#include <deque>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace rtabmap::optimizer_internal {

namespace {

// Link::isValid()'s rules (defined type, finite non-null transform, finite symmetric
// positive-definite information) without building its message: the optimiser checks every link
// of the graph at every update. The message comes from Link::isValid() when this fails.
bool looksValid(const Link& link) {
  if (Link::typeFromInt(link.type()) == Link::kUndef) return false;
  const Transform& t = link.transform();
  if (t.isNull() || t.isInvalid()) return false;
  const Link::InfMatrix& info = link.infMatrix();
  if (!info.allFinite()) return false;
  const double scale = std::max(1.0, info.cwiseAbs().maxCoeff());
  if ((info - info.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) return false;
  return Eigen::LLT<Link::InfMatrix>(info).info() == Eigen::Success;
}

}  // namespace

bool defaultRoot(const std::map<int, Transform>& poses, const std::multimap<int, Link>& links,
                 int* root) {
  if (!poses.empty() && poses.rbegin()->first >= 0) {
    *root = poses.rbegin()->first;
    return true;
  }
  bool found = false;
  for (const auto& [key, link] : links) {
    (void)key;
    for (int id : {link.from(), link.to()}) {
      if (id >= 0 && (!found || id > *root)) {
        *root = id;
        found = true;
      }
    }
  }
  return found;
}

bool selectGraph(const OptimizerOptions& options, const std::map<int, Transform>& poses,
                 const std::multimap<int, Link>& links, int root, SelectedGraph* selected,
                 OptimizerSummary* summary, std::string* why) {
  auto fail = [&](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  selected->root = root;
  const bool use3D = !options.force3DoF;

  // Nodes that exist: keys of `poses`, and landmarks reached by landmark links.
  std::unordered_set<int> landmarks;
  if (!options.landmarksIgnored) {
    for (const auto& [key, link] : links) {
      (void)key;
      if (link.type() != Link::kLandmark) continue;
      if (link.to() < 0) landmarks.insert(link.to());
      if (link.from() < 0) landmarks.insert(link.from());
    }
  }
  auto present = [&](int id) { return poses.count(id) != 0 || landmarks.count(id) != 0; };
  if (!present(root)) {
    std::ostringstream s;
    s << "the root node " << root << " is not in the graph (no pose given for it)";
    return fail(s.str());
  }

  // Classify the links.
  std::vector<const Link*> relative, priors, gravity;
  relative.reserve(links.size());
  for (const auto& [key, link] : links) {
    (void)key;
    if (!looksValid(link)) {
      std::string reason;
      link.isValid(&reason);
      if (reason.empty()) reason = "link " + std::to_string(link.from()) + "->" + std::to_string(link.to());
      return fail("invalid link: " + reason);
    }
    const Link::Type type = link.type();
    if (type == Link::kPosePrior) {
      if (options.priorsIgnored) {
        ++summary->linksIgnoredByOptions;
      } else if (!present(link.from())) {
        ++summary->linksToAbsentNodes;
      } else {
        priors.push_back(&link);
      }
      continue;
    }
    if (type == Link::kGravity) {
      if (options.gravitySigma <= 0.0 || !use3D) {
        ++summary->linksIgnoredByOptions;
      } else if (!present(link.from())) {
        ++summary->linksToAbsentNodes;
      } else {
        gravity.push_back(&link);
      }
      continue;
    }
    if (link.from() == link.to()) {
      std::ostringstream s;
      s << "invalid link: " << link.typeName() << " link " << link.from() << "->" << link.to()
        << " links a node to itself (only priors and gravity links may)";
      return fail(s.str());
    }
    if (type == Link::kLandmark && options.landmarksIgnored) {
      ++summary->linksIgnoredByOptions;
      continue;
    }
    if (!present(link.from()) || !present(link.to())) {
      ++summary->linksToAbsentNodes;
      continue;
    }
    relative.push_back(&link);
  }

  // The root's connected component.
  std::unordered_map<int, std::vector<int>> adj;
  adj.reserve(poses.size() + landmarks.size());
  for (const Link* link : relative) {
    adj[link->from()].push_back(link->to());
    adj[link->to()].push_back(link->from());
  }
  std::unordered_set<int> component{root};
  {
    std::deque<int> queue{root};
    while (!queue.empty()) {
      const int id = queue.front();
      queue.pop_front();
      const auto it = adj.find(id);
      if (it == adj.end()) continue;
      for (int next : it->second) {
        if (component.insert(next).second) queue.push_back(next);
      }
    }
  }
  selected->nodes.clear();
  selected->nodes.insert(component.begin(), component.end());

  selected->relative.clear();
  for (const Link* link : relative) {
    if (component.count(link->from())) {
      selected->relative.emplace_hint(selected->relative.end(), link->from(), *link);
    } else {
      ++summary->linksOutsideRootComponent;
    }
  }
  for (const Link* link : priors) {
    if (component.count(link->from())) {
      selected->priors.push_back(*link);
    } else {
      ++summary->linksOutsideRootComponent;
    }
  }
  for (const Link* link : gravity) {
    if (component.count(link->from())) {
      selected->gravity.push_back(*link);
    } else {
      ++summary->linksOutsideRootComponent;
    }
  }
  for (const auto& [id, pose] : poses) {
    if (!component.count(id)) {
      ++summary->nodesOutsideRootComponent;
    } else if (pose.isInvalid()) {
      std::ostringstream s;
      s << "the input pose of node " << id << " is not finite";
      return fail(s.str());
    }
  }
  summary->otherComponentsLeftOut = summary->nodesOutsideRootComponent > 0;
  summary->nodes = static_cast<int>(selected->nodes.size());
  summary->links = static_cast<int>(selected->relative.size());
  summary->priors = static_cast<int>(selected->priors.size());
  summary->gravityLinks = static_cast<int>(selected->gravity.size());
  return true;
}

}  // namespace rtabmap::optimizer_internal

// graph:: connected components and the local map.
#include <algorithm>
#include <deque>
#include <unordered_map>
#include <vector>

#include "rtabmap_core/optimizer/Graph.h"

namespace rtabmap::graph {

namespace {

// Undirected adjacency of the links between distinct nodes accepted by `accept`.
template <typename Accept>
std::unordered_map<int, std::vector<int>> adjacency(const Links& links, Accept accept) {
  std::unordered_map<int, std::vector<int>> adj;
  for (const auto& [key, link] : links) {
    (void)key;
    if (link.from() == link.to() || !accept(link.from()) || !accept(link.to())) continue;
    adj[link.from()].push_back(link.to());
    adj[link.to()].push_back(link.from());
  }
  return adj;
}

std::set<int> breadthFirst(int root, const std::unordered_map<int, std::vector<int>>& adj) {
  std::set<int> seen{root};
  std::deque<int> queue{root};
  while (!queue.empty()) {
    const int id = queue.front();
    queue.pop_front();
    const auto it = adj.find(id);
    if (it == adj.end()) continue;
    for (int next : it->second) {
      if (seen.insert(next).second) queue.push_back(next);
    }
  }
  return seen;
}

}  // namespace

// Union-find over the links' ends: one pass over the links, no adjacency lists (the SLAM update
// asks for the new node's component of the whole local map at every optimisation).
std::set<int> connectedComponent(int root, const Links& links, const std::set<int>* allowed) {
  if (allowed && !allowed->count(root)) return {};
  std::unordered_map<int, int> index;  // node id -> its entry in parent
  index.reserve(links.size() + 1);
  std::vector<int> parent, ids;
  auto entry = [&](int id) {
    const auto [it, inserted] = index.emplace(id, static_cast<int>(parent.size()));
    if (inserted) {
      parent.push_back(it->second);
      ids.push_back(id);
    }
    return it->second;
  };
  auto find = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];  // path halving
    return i;
  };
  entry(root);
  for (const auto& [key, link] : links) {
    (void)key;
    if (link.from() == link.to()) continue;
    if (allowed && (!allowed->count(link.from()) || !allowed->count(link.to()))) continue;
    const int a = find(entry(link.from())), b = find(entry(link.to()));
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  std::vector<int> component;
  const int r = find(0);
  for (size_t i = 0; i < ids.size(); ++i) {
    if (find(static_cast<int>(i)) == r) component.push_back(ids[i]);
  }
  std::sort(component.begin(), component.end());
  return std::set<int>(component.begin(), component.end());  // sorted: linear
}

std::vector<std::set<int>> connectedComponents(const Poses& poses, const Links& links) {
  const auto adj = adjacency(links, [&](int id) { return poses.count(id) != 0; });
  std::vector<std::set<int>> components;
  std::set<int> assigned;
  for (const auto& [id, pose] : poses) {
    (void)pose;
    if (assigned.count(id)) continue;
    std::set<int> component = breadthFirst(id, adj);
    assigned.insert(component.begin(), component.end());
    components.push_back(std::move(component));
  }
  // Stable: components were found in increasing first id, so ties keep that order.
  std::stable_sort(components.begin(), components.end(),
                   [](const std::set<int>& a, const std::set<int>& b) { return a.size() > b.size(); });
  return components;
}

Subgraph localMap(int root, const Poses& poses, const Links& links) {
  Subgraph out;
  if (!poses.count(root)) return out;
  const auto adj = adjacency(links, [&](int id) { return poses.count(id) != 0; });
  const std::set<int> ids = breadthFirst(root, adj);
  for (int id : ids) out.poses.emplace(id, poses.at(id));
  for (const auto& entry : links) {
    const Link& link = entry.second;
    if (ids.count(link.from()) && ids.count(link.to())) out.links.insert(out.links.end(), entry);
  }
  return out;
}

}  // namespace rtabmap::graph

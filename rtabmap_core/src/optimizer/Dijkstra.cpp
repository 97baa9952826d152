// graph:: cheapest paths in the pose graph (Dijkstra), with the distance or travel-time cost.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <unordered_map>

#include "PoseMath.h"
#include "rtabmap_core/optimizer/Graph.h"

namespace rtabmap::graph {

double linkCost(const Transform& from, const Transform& to, const PathCost& cost) {
  const double distance = poseDistance(from, to, cost.is2D);
  if (cost.linearVelocity <= 0.0 && cost.angularVelocity <= 0.0) return distance;
  double total = cost.linearVelocity > 0.0 ? distance / cost.linearVelocity : distance;
  if (cost.angularVelocity > 0.0) {
    const double turn = cost.is2D
                            ? std::fabs(optimizer_internal::wrapAngle(to.yaw() - from.yaw()))
                            : (from.inverse() * to).getAngle();
    total += turn / cost.angularVelocity;
  }
  return total;
}

Path computePath(const Poses& poses, const Links& links, int from, int to, const PathCost& cost) {
  Path path;
  const auto fromIt = poses.find(from);
  const auto toIt = poses.find(to);
  if (fromIt == poses.end() || toIt == poses.end() || fromIt->second.isNull() ||
      toIt->second.isNull()) {
    return path;
  }
  // Neighbours with their edge cost; a pair of nodes linked several times keeps one edge (the
  // cost depends on the poses only).
  std::unordered_map<int, std::map<int, double>> adj;
  for (const auto& [key, link] : links) {
    (void)key;
    if (link.from() == link.to()) continue;
    const auto a = poses.find(link.from());
    const auto b = poses.find(link.to());
    if (a == poses.end() || b == poses.end() || a->second.isNull() || b->second.isNull()) continue;
    adj[link.from()][link.to()] = linkCost(a->second, b->second, cost);
    adj[link.to()][link.from()] = linkCost(b->second, a->second, cost);
  }

  using Entry = std::pair<double, int>;  // cost so far, node
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  std::unordered_map<int, double> best{{from, 0.0}};
  std::unordered_map<int, int> previous;
  open.emplace(0.0, from);
  while (!open.empty()) {
    const auto [soFar, id] = open.top();
    open.pop();
    if (soFar > best.at(id)) continue;  // stale entry
    if (id == to) break;
    const auto it = adj.find(id);
    if (it == adj.end()) continue;
    for (const auto& [next, edge] : it->second) {
      const double candidate = soFar + edge;
      const auto known = best.find(next);
      if (known == best.end() || candidate < known->second) {
        best[next] = candidate;
        previous[next] = id;
        open.emplace(candidate, next);
      }
    }
  }
  if (!best.count(to)) return path;
  path.found = true;
  path.cost = best.at(to);
  for (int id = to;; id = previous.at(id)) {
    path.nodes.emplace_back(id, poses.at(id));
    if (id == from) break;
  }
  std::reverse(path.nodes.begin(), path.nodes.end());
  return path;
}

}  // namespace rtabmap::graph

// The building's navigation graph: nodes on corridor centre lines (junctions, door fronts) and
// in rooms (visit points), edges along the corridors and through doorways.
#include <algorithm>
#include <limits>
#include <queue>

#include "BuildingInternal.h"

namespace rtabmap::sim {

int NavGraph::addNode(const NavNode& node) {
  nodes_.push_back(node);
  edges_.emplace_back();
  return static_cast<int>(nodes_.size()) - 1;
}

void NavGraph::addEdge(int a, int b, const std::vector<Eigen::Vector2d>& viaFromA) {
  double length = 0.0;
  Eigen::Vector2d previous = nodes_[static_cast<size_t>(a)].position;
  for (const auto& p : viaFromA) {
    length += (p - previous).norm();
    previous = p;
  }
  length += (nodes_[static_cast<size_t>(b)].position - previous).norm();
  edges_[static_cast<size_t>(a)].push_back({b, length, viaFromA});
  std::vector<Eigen::Vector2d> reversed(viaFromA.rbegin(), viaFromA.rend());
  edges_[static_cast<size_t>(b)].push_back({a, length, reversed});
}

const NavEdge* NavGraph::edge(int a, int b) const {
  for (const NavEdge& e : edges_[static_cast<size_t>(a)]) {
    if (e.to == b) return &e;
  }
  return nullptr;
}

std::vector<int> NavGraph::shortestPath(int a, int b) const {
  const size_t n = nodes_.size();
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<int> previous(n, -1);
  using Entry = std::pair<double, int>;  // ties broken by node index: deterministic
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  dist[static_cast<size_t>(a)] = 0.0;
  queue.emplace(0.0, a);
  while (!queue.empty()) {
    const auto [d, u] = queue.top();
    queue.pop();
    if (d > dist[static_cast<size_t>(u)]) continue;
    if (u == b) break;
    for (const NavEdge& e : edges_[static_cast<size_t>(u)]) {
      const double nd = d + e.length;
      if (nd < dist[static_cast<size_t>(e.to)]) {
        dist[static_cast<size_t>(e.to)] = nd;
        previous[static_cast<size_t>(e.to)] = u;
        queue.emplace(nd, e.to);
      }
    }
  }
  if (a != b && previous[static_cast<size_t>(b)] < 0) return {};
  std::vector<int> path;
  for (int v = b; v != -1; v = previous[static_cast<size_t>(v)]) {
    path.push_back(v);
    if (v == a) break;
  }
  std::reverse(path.begin(), path.end());
  return path;
}

int NavGraph::junction(int i, int j) const {
  for (size_t k = 0; k < nodes_.size(); ++k) {
    if (nodes_[k].kind == NavNodeKind::kJunction && nodes_[k].gridX == i && nodes_[k].gridY == j) return static_cast<int>(k);
  }
  return -1;
}

std::vector<Eigen::Vector2d> NavGraph::waypoints(const std::vector<int>& path) const {
  std::vector<Eigen::Vector2d> points;
  for (size_t k = 0; k < path.size(); ++k) {
    if (k > 0) {
      const NavEdge* e = edge(path[k - 1], path[k]);
      if (e) points.insert(points.end(), e->via.begin(), e->via.end());
    }
    points.push_back(nodes_[static_cast<size_t>(path[k])].position);
  }
  return points;
}

namespace detail {

void buildNavGraph(Context& ctx) {
  Building& b = ctx.building;
  NavGraph& g = b.nav;
  const double half = 0.5 * ctx.spec.corridorWidth;
  // Nodes on each corridor centre line, with their coordinate along it.
  std::vector<std::vector<std::pair<double, int>>> onH(ctx.corrY.size()), onV(ctx.corrX.size());
  for (size_t j = 0; j < ctx.corrY.size(); ++j) {
    for (size_t i = 0; i < ctx.corrX.size(); ++i) {
      NavNode n;
      n.kind = NavNodeKind::kJunction;
      n.position = {ctx.corrX[i] + half, ctx.corrY[j] + half};
      n.area = ctx.corridorH[j];
      n.gridX = static_cast<int>(i);
      n.gridY = static_cast<int>(j);
      const int id = g.addNode(n);
      onH[j].emplace_back(n.position.x(), id);
      onV[i].emplace_back(n.position.y(), id);
    }
  }
  for (size_t d = 0; d < b.doors.size(); ++d) {
    const Door& door = b.doors[d];
    NavNode front;
    front.kind = NavNodeKind::kDoorFront;
    front.position = door.front;
    front.area = door.corridor;
    front.door = static_cast<int>(d);
    const int frontId = g.addNode(front);
    for (size_t j = 0; j < ctx.corridorH.size(); ++j) {
      if (ctx.corridorH[j] == door.corridor) onH[j].emplace_back(door.front.x(), frontId);
    }
    for (size_t i = 0; i < ctx.corridorV.size(); ++i) {
      if (ctx.corridorV[i] == door.corridor) onV[i].emplace_back(door.front.y(), frontId);
    }
    NavNode room;
    room.kind = NavNodeKind::kRoom;
    room.position = b.areas[static_cast<size_t>(door.room)].visitPoint;
    room.area = door.room;
    room.door = static_cast<int>(d);
    const int roomId = g.addNode(room);
    // Straight through the doorway: front -> door centre -> 0.9 m inside -> visit point.
    g.addEdge(frontId, roomId, {door.centre, door.inside});
  }
  for (auto* lines : {&onH, &onV}) {
    for (auto& line : *lines) {
      std::sort(line.begin(), line.end());
      for (size_t k = 0; k + 1 < line.size(); ++k) g.addEdge(line[k].second, line[k + 1].second);
    }
  }
}

}  // namespace detail
}  // namespace rtabmap::sim

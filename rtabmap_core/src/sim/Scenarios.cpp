#include "rtabmap_core/sim/Scenarios.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rtabmap_core/sim/Random.h"

namespace rtabmap::sim {

namespace {

// A route under construction: a sequence of navigation nodes.
class RouteBuilder {
 public:
  RouteBuilder(const NavGraph& graph, int start) : g_(graph) { nodes_.push_back(start); }

  // The shortest path from the last node to `target`.
  void goTo(int target) {
    const std::vector<int> path = g_.shortestPath(nodes_.back(), target);
    if (path.empty()) throw std::logic_error("route: unreachable navigation node");
    for (size_t k = 1; k < path.size(); ++k) append(path[k]);
  }
  // Goes into the room of door-front node `front` and back out (front must be on the route).
  void visit(int front) {
    const int room = roomOf(front);
    if (room < 0) return;
    for (size_t k = 0; k < nodes_.size(); ++k) {
      if (nodes_[k] == front) {
        nodes_.insert(nodes_.begin() + static_cast<std::ptrdiff_t>(k) + 1, {room, front});
        return;
      }
    }
  }
  // Into the room behind the last node (a door front) and back out, at the end of the route.
  void visitHere() {
    const int front = nodes_.back();
    const int room = roomOf(front);
    if (room < 0) return;
    append(room);
    append(front);
  }
  int roomOf(int front) const {
    for (const NavEdge& e : g_.edges(front)) {
      if (g_.nodes()[static_cast<size_t>(e.to)].kind == NavNodeKind::kRoom) return e.to;
    }
    return -1;
  }
  // Door fronts on the shortest path between two nodes (both excluded).
  std::vector<int> frontsBetween(int a, int b) const {
    std::vector<int> out;
    const std::vector<int> path = g_.shortestPath(a, b);
    for (size_t k = 1; k + 1 < path.size(); ++k) {
      if (g_.nodes()[static_cast<size_t>(path[k])].kind == NavNodeKind::kDoorFront) out.push_back(path[k]);
    }
    return out;
  }
  // The middle door front between two junctions, or `fallback`.
  int middleFront(int a, int b, int fallback) const {
    const std::vector<int> fronts = frontsBetween(a, b);
    return fronts.empty() ? fallback : fronts[fronts.size() / 2];
  }
  const std::vector<int>& nodes() const { return nodes_; }
  double length() const { return length_; }
  int pivots() const { return pivots_; }

 private:
  void append(int node) {
    if (node == nodes_.back()) return;
    const NavEdge* e = g_.edge(nodes_.back(), node);
    length_ += e ? e->length : (g_.nodes()[static_cast<size_t>(node)].position - g_.nodes()[static_cast<size_t>(nodes_.back())].position).norm();
    if (nodes_.size() >= 2 && nodes_[nodes_.size() - 2] == node) ++pivots_;  // turning back
    nodes_.push_back(node);
  }

  const NavGraph& g_;
  std::vector<int> nodes_;
  double length_ = 0.0;
  int pivots_ = 0;
};

// Room visits on door fronts of a route part: one into a block room and one into a band room
// when both exist (they look different: block rooms are inner offices).
std::vector<int> pickVisits(const Building& b, const RouteBuilder& route, const std::vector<int>& candidates, int count) {
  std::vector<int> picked;
  std::vector<bool> isBlockRoom;
  for (int f : candidates) {
    const Door& door = b.doors[static_cast<size_t>(b.nav.nodes()[static_cast<size_t>(f)].door)];
    const Rect& r = b.areas[static_cast<size_t>(door.room)].rect;
    bool inBlock = false;
    for (const Rect& block : b.blocks) inBlock = inBlock || block.contains(r.centre());
    isBlockRoom.push_back(inBlock);
  }
  for (int pass = 0; pass < 2 && static_cast<int>(picked.size()) < count; ++pass) {
    for (size_t k = candidates.size() / 3; k < candidates.size(); ++k) {
      if (static_cast<int>(picked.size()) >= count) break;
      if (route.roomOf(candidates[k]) < 0) continue;
      // First pass: alternate block room, band room, block room...
      const bool wantBlock = (picked.size() % 2 == 0);
      if (pass == 0 && isBlockRoom[k] != wantBlock) continue;
      if (std::find(picked.begin(), picked.end(), candidates[k]) != picked.end()) continue;
      picked.push_back(candidates[k]);
    }
  }
  return picked;
}

SessionRoute finish(const Building& b, const RouteBuilder& route, const std::string& name) {
  SessionRoute s;
  s.name = name;
  s.nodes = route.nodes();
  s.waypoints = b.nav.waypoints(route.nodes());
  return s;
}

// The door fronts of a closed lap (through the given junctions, in order).
std::vector<int> lapFronts(const RouteBuilder& route, const std::vector<int>& corners) {
  std::vector<int> out;
  for (size_t k = 0; k < corners.size(); ++k) {
    const auto part = route.frontsBetween(corners[k], corners[(k + 1) % corners.size()]);
    out.insert(out.end(), part.begin(), part.end());
  }
  return out;
}

std::vector<SessionRoute> loopRoutes(const Building& b, bool reverse) {
  const NavGraph& g = b.nav;
  const int j00 = g.junction(0, 0), j10 = g.junction(1, 0), j11 = g.junction(1, 1), j01 = g.junction(0, 1);
  RouteBuilder probe(g, j00);
  const int start = probe.middleFront(j00, j10, j00);
  RouteBuilder route(g, start);
  for (int corner : {j10, j11, j01, j00}) route.goTo(corner);
  route.goTo(start);
  for (int f : pickVisits(b, route, lapFronts(route, {j10, j11, j01, j00}), reverse ? 1 : 2)) route.visit(f);
  if (reverse) {
    // Turn round and drive the lap the other way.
    for (int corner : {j00, j01, j11, j10}) route.goTo(corner);
    route.goTo(start);
  } else {
    // Along the first third of the lap again, in the same direction.
    route.goTo(j10);
    route.goTo(probe.middleFront(j10, j11, j11));
  }
  return {finish(b, route, "")};
}

std::vector<SessionRoute> corridorRoutes(const Building& b) {
  const NavGraph& g = b.nav;
  RouteBuilder route(g, g.junction(0, 0));
  route.goTo(g.junction(b.junctionsX - 1, 0));
  route.goTo(g.junction(0, 0));
  return {finish(b, route, "")};
}

std::vector<SessionRoute> multisessionRoutes(const Building& b) {
  const NavGraph& g = b.nav;
  const int j00 = g.junction(0, 0), j10 = g.junction(1, 0), j20 = g.junction(2, 0);
  const int j01 = g.junction(0, 1), j11 = g.junction(1, 1), j21 = g.junction(2, 1);
  std::vector<SessionRoute> out;
  {  // Run 1: round the west block, counter-clockwise, from the middle of the south corridor.
    RouteBuilder probe(g, j00);
    const int s = probe.middleFront(j00, j10, j00);
    RouteBuilder r(g, s);
    for (int c : {j10, j11, j01, j00}) r.goTo(c);
    r.goTo(s);
    for (int f : pickVisits(b, r, lapFronts(r, {j10, j11, j01, j00}), 1)) r.visit(f);
    out.push_back(finish(b, r, "session1"));
  }
  {  // Run 2: round the east block, clockwise, from the east corridor: shares the middle one.
    RouteBuilder probe(g, j20);
    const int s = probe.middleFront(j20, j21, j20);
    RouteBuilder r(g, s);
    for (int c : {j20, j10, j11, j21}) r.goTo(c);
    r.goTo(s);
    for (int f : pickVisits(b, r, lapFronts(r, {j20, j10, j11, j21}), 1)) r.visit(f);
    out.push_back(finish(b, r, "session2"));
  }
  {  // Run 3: starts inside a room on the north corridor, then crosses both earlier runs.
    RouteBuilder probe(g, j11);
    const int front = probe.middleFront(j11, j21, j11);
    const int room = probe.roomOf(front);
    RouteBuilder r(g, room >= 0 ? room : front);
    if (room >= 0) r.goTo(front);
    for (int c : {j11, j01, j00, j10, j20}) r.goTo(c);
    out.push_back(finish(b, r, "session3"));
  }
  return out;
}

std::vector<SessionRoute> longRoutes(const Building& b, uint64_t seed, const MotionLimits& limits, double target) {
  const NavGraph& g = b.nav;
  Rng rng(seed, "route/long");
  std::vector<int> fronts;
  std::vector<int> junctions;
  for (size_t k = 0; k < g.nodes().size(); ++k) {
    if (g.nodes()[k].kind == NavNodeKind::kDoorFront) fronts.push_back(static_cast<int>(k));
    if (g.nodes()[k].kind == NavNodeKind::kJunction) junctions.push_back(static_cast<int>(k));
  }
  RouteBuilder route(g, g.junction(0, 0));
  // Mean speed with corners and stops is about 80% of the top speed; in-place turns and room
  // visits take a few seconds each. Extend until the estimate clears the target, then check the
  // real plan and extend again if needed.
  auto estimate = [&]() { return route.length() / (0.8 * limits.maxSpeed) + 5.0 * route.pivots(); };
  double goal = target;
  while (true) {
    while (estimate() < goal) {
      switch (rng.weighted({0.45, 0.35, 0.2})) {
        case 0: {  // a lap round a block, either way, from its nearest corner
          const int bi = rng.uniformInt(0, b.junctionsX - 2);
          const int bj = rng.uniformInt(0, b.junctionsY - 2);
          std::vector<int> corners = {g.junction(bi, bj), g.junction(bi + 1, bj), g.junction(bi + 1, bj + 1), g.junction(bi, bj + 1)};
          if (rng.chance(0.5)) std::reverse(corners.begin(), corners.end());
          const Eigen::Vector2d here = g.nodes()[static_cast<size_t>(route.nodes().back())].position;
          size_t first = 0;
          for (size_t k = 1; k < corners.size(); ++k) {
            if ((g.nodes()[static_cast<size_t>(corners[k])].position - here).norm() <
                (g.nodes()[static_cast<size_t>(corners[first])].position - here).norm()) {
              first = k;
            }
          }
          for (size_t k = 0; k <= corners.size(); ++k) route.goTo(corners[(first + k) % corners.size()]);
          break;
        }
        case 1: {  // a room
          route.goTo(rng.pick(fronts));
          route.visitHere();
          break;
        }
        default:
          route.goTo(rng.pick(junctions));
      }
    }
    SessionRoute s = finish(b, route, "");
    const double planned = ReferencePath(s.waypoints, limits).duration();
    if (planned >= target) return {s};
    goal = estimate() + 1.1 * (target - planned) + 30.0;  // the estimate was optimistic: go on
  }
}

}  // namespace

std::vector<std::string> scenarioNames() { return {"corridor", "long", "loop", "multisession", "reverse"}; }

ScenarioSpec scenarioSpec(const std::string& name) {
  ScenarioSpec s;
  s.name = name;
  if (name == "loop" || name == "reverse") {
    s.description = name == "loop" ? "a lap of a ring corridor round a block of rooms, then a third of it again (same direction)"
                                   : "a lap of a ring corridor, then the same lap driven the other way";
    s.building.blocksX = 1;
    s.building.blocksY = 1;
    s.building.blockMinWidth = 12.0;
    s.building.blockMaxWidth = 14.0;
    s.building.blockMinDepth = 8.0;
    s.building.blockMaxDepth = 10.0;
  } else if (name == "corridor") {
    s.description = "a long corridor with plain walls and ceiling, driven to the far end and back";
    s.building.blocksX = 1;
    s.building.blocksY = 1;
    s.building.blockMinWidth = 40.0;
    s.building.blockMaxWidth = 44.0;
    s.building.blockMinDepth = 6.0;
    s.building.blockMaxDepth = 6.2;
    s.building.outerRoomDepth = 0.0;
    s.building.plainCorridors = true;
    s.building.plainWallShare = 0.8;
    s.building.roomMinWidth = 4.0;
    s.building.roomMaxWidth = 8.0;
  } else if (name == "multisession") {
    s.description = "three runs in a two-block building, each starting elsewhere with odometry reset, each overlapping an earlier one";
    s.building.blocksX = 2;
    s.building.blocksY = 1;
    s.sessions = 3;
  } else if (name == "long") {
    s.description = "a two-hour random tour of a large building (laps and room visits, many revisits)";
    s.building.blocksX = 4;
    s.building.blocksY = 3;
    s.defaultRate = 1.0;
    s.targetDuration = 7200.0;
  } else {
    std::string known;
    for (const auto& n : scenarioNames()) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown scenario \"" + name + "\" (known: " + known + ")");
  }
  return s;
}

std::vector<SessionRoute> planRoutes(const ScenarioSpec& spec, const Building& building, uint64_t seed,
                                     const MotionLimits& limits, double targetDuration) {
  if (spec.name == "loop") return loopRoutes(building, false);
  if (spec.name == "reverse") return loopRoutes(building, true);
  if (spec.name == "corridor") return corridorRoutes(building);
  if (spec.name == "multisession") return multisessionRoutes(building);
  if (spec.name == "long") {
    return longRoutes(building, seed, limits, targetDuration > 0.0 ? targetDuration : spec.targetDuration);
  }
  throw std::invalid_argument("planRoutes: unknown scenario \"" + spec.name + "\"");
}

}  // namespace rtabmap::sim

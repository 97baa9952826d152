#pragma once
// Graph utilities on the pose graph of RTAB-Map: nodes are ids with poses
// (std::map<int, Transform>), links are std::multimap<int, Link> keyed by their `from` id (the
// form Signature and Database use). Links are undirected for connectivity and paths.
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap::graph {

using Poses = std::map<int, Transform>;
using Links = std::multimap<int, Link>;

// ---- Link filtering -----------------------------------------------------------------------------
// The links whose type is in `types` (keep = true), or those whose type is not (keep = false).
Links filterLinks(const Links& links, const std::set<Link::Type>& types, bool keep = false);
Links filterLinks(const Links& links, Link::Type type, bool keep = false);
// Loop closures and proximity links (global, local space, local time, user closures).
bool isLoopClosureOrProximity(Link::Type type);
// Drops a link when its reverse (to -> from, same type, inverse transform within 1e-6) was kept
// already: what a multimap holding both directions of every link (Signature::getLinks() of all
// nodes) needs before optimisation.
Links filterDuplicateLinks(const Links& links);
// The first link between a and b (either direction if bothWays), of type `type` unless kUndef;
// links.end() if none.
Links::const_iterator findLink(const Links& links, int a, int b, bool bothWays = true,
                               Link::Type type = Link::kUndef);

// ---- Connectivity -------------------------------------------------------------------------------
// Ids connected to `root` (root included) through links whose both ends satisfy `allowed`
// (all nodes if allowed is null). Priors and gravity links (from == to) connect nothing.
std::set<int> connectedComponent(int root, const Links& links, const std::set<int>* allowed = nullptr);
// The connected components of the nodes of `poses` through the links between them, largest
// first (ties: smallest first id first).
std::vector<std::set<int>> connectedComponents(const Poses& poses, const Links& links);

// The local map of a node (the "connected local graph" of the papers): the largest connected
// graph from `root` through links whose both ends are in `poses` (e.g. the nodes of Working
// Memory near the robot), with the poses and links of that graph. Empty if root is not in
// `poses`.
struct Subgraph {
  Poses poses;
  Links links;
};
Subgraph localMap(int root, const Poses& poses, const Links& links);

// ---- Nearest nodes ------------------------------------------------------------------------------
// Distance between two poses' positions (x, y only if is2D).
double poseDistance(const Transform& a, const Transform& b, bool is2D = false);
// The k nodes of `poses` nearest to `target` (id, distance), nearest first; ties by id.
std::vector<std::pair<int, double>> findNearestNodes(const Poses& poses, const Transform& target,
                                                      int k, bool is2D = false);
// The nearest node, or 0 with *distance untouched if poses is empty.
int findNearestNode(const Poses& poses, const Transform& target, double* distance = nullptr,
                    bool is2D = false);
// Every node within `radius` (inclusive) of `target`: id -> distance. With maxAngle > 0, only
// the nodes whose orientation differs from the target's by at most maxAngle (radians; yaw only
// if is2D).
std::map<int, double> findNodesInRadius(const Poses& poses, const Transform& target, double radius,
                                        bool is2D = false, double maxAngle = 0.0);

// ---- Paths (Dijkstra) ---------------------------------------------------------------------------
// Cost of a link between two nodes, from their poses. With both velocities 0 it is the distance
// (metres). Otherwise it is the travel time of the SPLAM paper's planner (Autonomous Robots 2017),
// where turning costs too: distance / linearVelocity (or the distance if linearVelocity is 0)
// plus |heading change| / angularVelocity (if angularVelocity > 0), the heading change being
// the rotation between the two nodes' orientations (yaw if is2D, else the full angle).
struct PathCost {
  double linearVelocity = 0.0;   // m/s; RGBD/PlanLinearVelocity
  double angularVelocity = 0.0;  // rad/s; RGBD/PlanAngularVelocity
  bool is2D = false;
};
double linkCost(const Transform& from, const Transform& to, const PathCost& cost);

struct Path {
  bool found = false;
  double cost = 0.0;
  // from ... to with their poses; empty if not found.
  std::vector<std::pair<int, Transform>> nodes;
};
// Cheapest path from `from` to `to` through the links whose both ends are in `poses`, whatever
// their type (virtual links of path planning included: the cost comes from the poses, not from
// the link's transform). Deterministic when several paths have the same cost. Not found if
// either end is not in `poses` or no path exists.
Path computePath(const Poses& poses, const Links& links, int from, int to,
                 const PathCost& cost = PathCost());

}  // namespace rtabmap::graph

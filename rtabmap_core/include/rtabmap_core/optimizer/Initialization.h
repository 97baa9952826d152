#pragma once
// First estimates of a pose graph, before Levenberg-Marquardt. Local solvers started from
// odometry stall in local minima on graphs with large loops (M3500, sphere); both methods below
// start near the optimum instead.
//
// Both work on the component of `root` in `links` (relative links only: links with from == to
// are skipped), put the root at `rootPose` (identity if null) and return a pose for every node
// of that component. With is2D, poses are x, y, yaw (Transform(x, y, theta)) and links are
// taken as their 3DoF part.
#include <map>
#include <set>
#include <string>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap::graph {

// Breadth-first spanning tree from the root: each newly reached node gets the pose of the node
// it was reached from composed with the link (or its inverse when walked backwards). Neighbours
// are visited in the order of `links`.
//  - odometryFirst: the tree first grows along odometry links (kNeighbor, kNeighborMerged) only,
//    then along any link: on a trajectory this is the dead-reckoning estimate.
//  - known: nodes that have a non-null pose there keep it (in the root's frame) instead of
//    being composed; the others are composed from them ("input poses" initialisation).
std::map<int, Transform> spanningTreeInitialization(int root, const Transform& rootPose,
                                                    const std::multimap<int, Link>& links,
                                                    bool is2D, bool odometryFirst = false,
                                                    const std::map<int, Transform>* known = nullptr);
// The spanning tree's result when every node of a connected graph is known: `nodes` at their
// pose in `known` (x, y, yaw in 2D; a normalised quaternion in 3D), without walking the graph.
// Empty if one of them has no non-null pose there (then the tree composes it).
std::map<int, Transform> knownPosesInitialization(const std::set<int>& nodes,
                                                  const std::map<int, Transform>& known, bool is2D);

// Chordal relaxation (Carlone et al., ICRA 2015; Martinec and Pajdla for rotations): rotations
// first, relaxed to 3x3 (2x2 in 2D) matrices so that R_j = R_i * R_ij is linear, solved by
// weighted sparse linear least squares with the root's rotation fixed, then projected back to
// rotations; positions second, by linear least squares on t_j - t_i = R_i * t_ij with those
// rotations. Weights: the mean rotational information of each link for rotations, and its
// translational information block rotated into the world for positions (identity for both with
// identityInformation). Returns an empty map and the reason in *why if a linear system cannot
// be solved (it cannot happen on a connected graph with positive-definite information).
std::map<int, Transform> chordalInitialization(int root, const Transform& rootPose,
                                               const std::multimap<int, Link>& links, bool is2D,
                                               bool identityInformation = false,
                                               std::string* why = nullptr);

}  // namespace rtabmap::graph

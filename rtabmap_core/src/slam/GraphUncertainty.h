#pragma once
// How well the graph knows where a node is relative to another one: the covariance of the
// relative 2D pose obtained by compounding the links of a chain between them (Smith, Self &
// Cheeseman 1990, "Estimating uncertain spatial relationships in robotics": first-order
// propagation of each link's covariance through the composition of the chain). The chain taken
// is the one of least accumulated position variance (Dijkstra), so a single strong path is
// enough to know a place, and weak links (merged-scan proximity links) only count where they
// are the only way through.
//
// Proximity detection uses it to bound its correlative search (RGBD/ProximityCorrelativeSigmas):
// where the graph is sure of the relative pose, a far better-scoring match is a look-alike.
#include <functional>
#include <map>

#include "rtabmap_core/memory/Link.h"

namespace rtabmap {

// Standard deviation (m, along the most uncertain direction) of each node's position relative to
// `root`, for the nodes whose best chain stays under `limit` m. `linksOf(id)` gives a node's
// links with their information matrices (null: node unknown). Virtual links (path planning) and
// links without a measurement (null transform, no information) do not connect nodes.
std::map<int, double> graphPositionSigmas(int root, double limit,
                                          const std::function<const std::multimap<int, Link>*(int)>& linksOf);

// Correlative search window (m) of a path whose nearest node has position sigma `sigma` relative
// to the new node (infinity when farther than any bound): `sigmas` standard deviations, never
// under ICP's reach (what ICP alone would correct) nor over `window`. sigmas 0 = `window`.
float correlativeWindowFor(double sigma, float window, float icpReach, float sigmas);

}  // namespace rtabmap

#pragma once
// Proximity detection by space (Labbé & Michaud, SPLAM paper, Autonomous Robots 2017, 3.3.3):
// loop closures found from where the graph says the robot is, not from what it sees. This is
// what closes a loop when the robot comes back the other way (the images do not match) or has
// no camera at all.
//
//  1. Candidates: the nodes of the local map (in RAM, optimised poses) within RGBD/LocalRadius
//     of the robot, at most RGBD/ProximityMaxGraphDepth links away, not in STM (those are the
//     robot's recent past: odometry links them already) and not linked to the new node yet.
//  2. Paths: the candidates grouped by neighbour links (pieces of earlier trajectories), most
//     recent first, at most RGBD/ProximityMaxPaths.
//  3. Per path whose node nearest to the robot is within RGBD/ProximityPathFilteringRadius:
//     visual registration with that node if it faces the same way (RGBD/ProximityAngle); else
//     (or when it fails) ICP of the new scan against the scans of the nearest node and its
//     RGBD/ProximityPathMaxNeighbors path neighbours on each side, merged in the nearest node's
//     frame (one-to-many), from the graph's relative pose as guess, refused when the scans'
//     structural complexity is under Icp/PointToPlaneMinComplexity (a corridor: ICP would only
//     echo the drifted guess along it); the covariance of a merged-scan link is multiplied by
//     RGBD/ProximityMergedScanCovFactor (the merged scan's own error is unknown).
//     With RGBD/ProximityCorrelativeWindow > 0 (2D scans), the ICP guess comes from a
//     correlative search of the merged scans around the graph's guess (CorrelativeScanMatcher.h):
//     after a long loop the graph can be metres off, beyond ICP's correspondence distance; paths
//     within that window (not only RGBD/ProximityPathFilteringRadius) are tried by scans. A
//     search whose best pose has a rival far from it scoring RGBD/ProximityCorrelativeMaxPeakRatio
//     of its score (corridors, look-alike hubs) links nothing: a wrong link pulls the graph more
//     than a missing one. The window of a path is also bounded by how wrong the graph can be
//     there (RGBD/ProximityCorrelativeSigmas standard deviations of the relative position of the
//     new node and the path's nearest node, GraphUncertainty.h): through a chain of strong links
//     (ICP-refined odometry, a place revisited moments ago) the graph's guess is good to a few
//     decimetres, and a pose metres away that scores better is a look-alike (the parallel
//     corridor behind a wall, the next door), not drift. Unbounded, such matches tore the Intel
//     map apart (issue 8): each link alone was weak enough to pass RGBD/OptimizeMaxError,
//     together they bent the graph. Bounded by the chain's length instead (a fixed drift per
//     metre), a short chain through weak merged-scan links counted as certain and ACES lost its
//     loop corrections: the chain's covariance widens the window exactly where it is weak.
#include <map>
#include <set>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"
#include "rtabmap_core/slam/RtabmapOptions.h"
#include "GraphUncertainty.h"

namespace rtabmap {

namespace memory {
class Memory;
}
class LinkRegistration;

struct ProximityResult {
  std::vector<Link> links;  // from the new node to the matched node
  int paths = 0;
  int visualChecked = 0, scanChecked = 0;
  int addedVisually = 0, addedByScans = 0;
  std::vector<std::string> rejections;  // why each tried registration failed
};

// `poses`: optimised poses of the nodes in RAM of the current referential (the new node
// included). Never throws on bad sensor data (a failed registration is a rejection).
ProximityResult detectProximityBySpace(memory::Memory& memory, int currentId, const std::map<int, Transform>& poses,
                                       const RtabmapOptions& options, const LinkRegistration& registration,
                                       bool covOffDiagIgnored);

// The ICP guess of a merged-scan match (2D) found by correlative scan matching within `window`
// (m) of `guess`, the pose of `scan` in `merged`'s frame (RGBD/ProximityCorrelative*); null with
// the reason when no pose scores RGBD/ProximityCorrelativeMinScore or a distant rival scores
// RGBD/ProximityCorrelativeMaxPeakRatio of the best.
Transform correlativeProximityGuess(const LaserScan& merged, const LaserScan& scan, const Transform& guess,
                                    const RtabmapOptions& options, float window, std::string* why);

// Paths of step 2, for tests: candidate ids grouped by neighbour links, most recent first.
std::vector<std::vector<int>> proximityPaths(const memory::Memory& memory, const std::set<int>& candidates);

}  // namespace rtabmap

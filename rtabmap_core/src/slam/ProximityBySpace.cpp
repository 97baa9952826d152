#include "ProximityBySpace.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "LinkRegistration.h"
#include "ScanMerge.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/memory/Memory.h"
#include "rtabmap_core/optimizer/Graph.h"
#include "rtabmap_core/registration/CorrelativeScanMatcher.h"
#include "rtabmap_core/registration/RegistrationInfo.h"

namespace rtabmap {
namespace {

bool isNeighborType(Link::Type t) { return t == Link::kNeighbor || t == Link::kNeighborMerged; }

double angleBetween(const Transform& a, const Transform& b, bool is2D) {
  const Transform d = a.inverse() * b;
  if (is2D) return std::fabs(d.theta());
  return std::fabs(d.getAngle());
}

std::set<int> candidatesOf(const memory::Memory& memory, int currentId, const std::map<int, Transform>& poses,
                           const RtabmapOptions& o) {
  const Transform& current = poses.at(currentId);
  const std::map<int, double> near = graph::findNodesInRadius(poses, current, o.localRadius, o.force3DoF);
  std::map<int, int> depth;
  if (o.proximityMaxGraphDepth > 0) depth = memory.neighbors(currentId, o.proximityMaxGraphDepth);
  const Signature* s = memory.signature(currentId);
  std::set<int> out;
  for (const auto& [id, distance] : near) {
    (void)distance;
    if (id == currentId || memory.stm().count(id) || !memory.inRam(id) || memory.isIntermediate(id)) continue;
    if (o.proximityMaxGraphDepth > 0 && !depth.count(id)) continue;
    if (s && s->hasLink(id)) continue;
    out.insert(id);
  }
  return out;
}

// The nodes of `path` nearest to `center` along it: center and up to n on each side.
std::vector<int> pathWindow(const std::vector<int>& path, int center, int n) {
  const auto it = std::find(path.begin(), path.end(), center);
  const long i = it - path.begin();
  const long first = std::max(0L, i - n), last = std::min(static_cast<long>(path.size()) - 1, i + n);
  return std::vector<int>(path.begin() + first, path.begin() + last + 1);
}

std::vector<Eigen::Vector2f> pointsInBase2d(const LaserScan& scan) {
  const LaserScan base = scan.transformedToBase();
  std::vector<Eigen::Vector2f> out;
  out.reserve(base.size());
  for (int i = 0; i < base.size(); ++i) out.push_back(base.point(i).head<2>());
  return out;
}

// Position sigma, relative to the new node, of the nodes the graph knows well enough to narrow
// the correlative window (the others get the whole window).
std::map<int, double> sigmasForWindow(const memory::Memory& memory, int currentId, const RtabmapOptions& o) {
  if (o.proximityCorrelativeWindow <= 0.0f || o.proximityCorrelativeSigmas <= 0.0f) return {};
  const double limit = o.proximityCorrelativeWindow / o.proximityCorrelativeSigmas;
  return graphPositionSigmas(currentId, limit, [&memory](int id) -> const std::multimap<int, Link>* {
    const Signature* s = memory.inRam(id) ? memory.signature(id) : nullptr;
    return s ? &s->getLinks() : nullptr;
  });
}

}  // namespace

Transform correlativeProximityGuess(const LaserScan& merged, const LaserScan& scan, const Transform& guess,
                                    const RtabmapOptions& o, float window, std::string* why) {
  CorrelativeOptions c;
  c.resolution = o.proximityCorrelativeResolution;
  c.linearWindow = window;
  c.angularWindow = o.proximityCorrelativeAngle * static_cast<float>(M_PI) / 180.0f;
  c.minScore = o.proximityCorrelativeMinScore;
  c.maxSecondPeakRatio = o.proximityCorrelativeMaxPeakRatio;
  const CorrelativeResult r = matchCorrelative(pointsInBase2d(merged), pointsInBase2d(scan),
                                               Eigen::Vector3f(guess.x(), guess.y(), guess.theta()), c);
  if (!r.found) {
    *why = r.why;
    return Transform();
  }
  return Transform(r.pose.x(), r.pose.y(), 0.0f, 0.0f, 0.0f, r.pose.z());
}

namespace {

// The nodes linked to `id` by neighbour links, through any chain of intermediate nodes
// (Rtabmap/CreateIntermediateNodes) in RAM: a path of the local map is of nodes, whatever lies
// between them.
std::vector<int> linkedThroughIntermediates(const memory::Memory& memory, int id) {
  std::vector<int> out;
  std::set<int> passed;
  std::vector<int> expand{id};
  while (!expand.empty()) {
    const Signature* s = memory.signature(expand.back());
    expand.pop_back();
    if (!s) continue;
    for (const auto& [to, link] : s->getLinks()) {
      if (!isNeighborType(link.type()) || to == id) continue;
      if (memory.inRam(to) && memory.isIntermediate(to)) {
        if (passed.insert(to).second) expand.push_back(to);
      } else {
        out.push_back(to);
      }
    }
  }
  return out;
}

}  // namespace

std::vector<std::vector<int>> proximityPaths(const memory::Memory& memory, const std::set<int>& candidates) {
  std::vector<std::vector<int>> paths;
  std::set<int> done;
  // Newest first: the path holding the most recent candidate comes first.
  for (auto it = candidates.rbegin(); it != candidates.rend(); ++it) {
    if (done.count(*it)) continue;
    std::vector<int> path;
    std::vector<int> stack{*it};
    done.insert(*it);
    while (!stack.empty()) {
      const int id = stack.back();
      stack.pop_back();
      path.push_back(id);
      for (int to : linkedThroughIntermediates(memory, id)) {
        if (!candidates.count(to) || !done.insert(to).second) continue;
        stack.push_back(to);
      }
    }
    std::sort(path.begin(), path.end());
    paths.push_back(std::move(path));
  }
  return paths;
}

ProximityResult detectProximityBySpace(memory::Memory& memory, int currentId, const std::map<int, Transform>& poses,
                                       const RtabmapOptions& o, const LinkRegistration& registration,
                                       bool covOffDiagIgnored) {
  ProximityResult result;
  if (!poses.count(currentId) || !memory.inRam(currentId)) return result;
  const Transform& currentPose = poses.at(currentId);
  std::vector<std::vector<int>> paths = proximityPaths(memory, candidatesOf(memory, currentId, poses, o));
  if (o.proximityMaxPaths > 0 && static_cast<int>(paths.size()) > o.proximityMaxPaths) paths.resize(o.proximityMaxPaths);
  result.paths = static_cast<int>(paths.size());
  Signature* current = memory.mutableSignature(currentId);
  const double maxAngle = o.proximityAngle * M_PI / 180.0;
  const bool correlative = o.proximityCorrelativeWindow > 0.0f;
  const std::map<int, double> sigmas = sigmasForWindow(memory, currentId, o);

  for (const std::vector<int>& path : paths) {
    std::map<int, Transform> pathPoses;
    for (int id : path) pathPoses.emplace(id, poses.at(id));
    double distance = 0.0;
    const int nearest = graph::findNearestNode(pathPoses, currentPose, &distance, o.force3DoF);
    // The path passes near the robot, but registration is tried only where the robot really is
    // back on it: farther, the overlap is partial and a link constrains little for its risk.
    // The correlative search of merged scans corrects drift up to its window, so it may look
    // that far.
    float window = 0.0f;
    if (correlative) {
      const auto it = sigmas.find(nearest);
      window = correlativeWindowFor(it != sigmas.end() ? it->second : std::numeric_limits<double>::infinity(),
                                    o.proximityCorrelativeWindow, registration.icpReach(),
                                    o.proximityCorrelativeSigmas);
    }
    const double scanRadius = std::max(o.proximityPathFilteringRadius, window);
    if (distance > scanRadius) {
      // A near miss says why a revisit was not linked (drift kept the robot just out of reach).
      if (distance <= 2.0 * scanRadius) {
        RTABMAP_DEBUG("proximity " << currentId << ": path " << path.front() << ".." << path.back() << " not tried, "
                                   << "its nearest node " << nearest << " is " << distance << " m away (radius "
                                   << scanRadius << " m, RGBD/ProximityPathFilteringRadius)");
      }
      continue;
    }
    const Transform guess = poses.at(currentId).inverse() * poses.at(nearest);  // current -> nearest

    // One-to-one visual registration with the nearest node, when it faces the same way.
    const bool visualOk = distance <= o.proximityPathFilteringRadius && registration.usesVision() &&
                          !current->isWordsEmpty() &&
                          angleBetween(currentPose, poses.at(nearest), o.force3DoF) <= maxAngle;
    if (visualOk) {
      ++result.visualChecked;
      RegistrationInfo info;
      Signature* other = memory.mutableSignature(nearest);
      const Transform t = registration.compute(*current, *other, o.proximityOdomGuess ? guess : Transform(), &info);
      if (!t.isNull()) {
        result.links.emplace_back(currentId, nearest, Link::kLocalSpaceClosure, t,
                                  informationOf(info.covariance, covOffDiagIgnored));
        ++result.addedVisually;
        continue;
      }
      result.rejections.push_back("visual proximity " + std::to_string(currentId) + "->" + std::to_string(nearest) +
                                  ": " + info.rejectedMsg);
    }

    // One-to-many scan matching against the merged scans of the path around the nearest node.
    if (!registration.usesScans() || o.proximityPathMaxNeighbors <= 0) continue;
    std::string problem;
    const LaserScan& scan = scanOf(*current, &problem);
    if (scan.empty()) continue;
    std::vector<std::pair<LaserScan, Transform>> parts;  // scan, pose in the nearest node's frame
    std::vector<int> partIds;
    const Signature* nearestSig = memory.signature(nearest);
    for (int id : pathWindow(path, nearest, o.proximityPathMaxNeighbors)) {
      Signature* s = memory.mutableSignature(id);
      const LaserScan& part = scanOf(*s);
      if (part.empty()) continue;
      const bool raw = o.proximityPathRawPosesUsed && !s->getPose().isNull() && !nearestSig->getPose().isNull() &&
                       s->mapId() == nearestSig->mapId();
      const Transform inNearest = raw ? nearestSig->getPose().inverse() * s->getPose()
                                      : poses.at(nearest).inverse() * poses.at(id);
      parts.emplace_back(part, inNearest);
      partIds.push_back(id);
    }
    if (parts.empty()) continue;
    ++result.scanChecked;
    const LaserScan merged = mergeScans(parts);
    RegistrationInfo info;
    Transform inv = guess.inverse();  // pose of the current node in the nearest node's frame
    if (correlative && merged.is2d() && scan.is2d()) {
      std::string why;
      inv = correlativeProximityGuess(merged, scan, inv, o, window, &why);
      if (inv.isNull()) {
        result.rejections.push_back("scan proximity " + std::to_string(currentId) + "->" + std::to_string(nearest) +
                                    ": " + why);
        continue;
      }
    }
    const Transform t = registration.icp(merged, scan, inv, &info);
    if (t.isNull()) {
      result.rejections.push_back("scan proximity " + std::to_string(currentId) + "->" + std::to_string(nearest) +
                                  ": " + info.rejectedMsg);
      continue;
    }
    // Scans that do not constrain every direction (a corridor) only echo the guess back along
    // the free one, and the guess is the drift the link is meant to correct.
    if (info.icpStructuralComplexity < registration.minComplexity()) {
      result.rejections.push_back("scan proximity " + std::to_string(currentId) + "->" + std::to_string(nearest) +
                                  ": structural complexity " + std::to_string(info.icpStructuralComplexity) +
                                  " under Icp/PointToPlaneMinComplexity");
      continue;
    }
    const Link fromNearest(nearest, currentId, Link::kLocalSpaceClosure, t,
                           informationOf(info.covariance * o.proximityMergedScanCovFactor, covOffDiagIgnored),
                           o.scanMatchingIdsSavedInLinks ? Link::scanIdsUserData(partIds) : cv::Mat());
    result.links.push_back(fromNearest.inverse());
    ++result.addedByScans;
  }
  return result;
}

}  // namespace rtabmap

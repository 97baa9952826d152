// The local map's graph: optimisation with the rejection of links the graph disagrees with
// (RGBD/OptimizeMaxError), and memory management around the robot (SPLAM paper, 3.3.4): what
// is retrieved near the robot and what stays immune from transfer.
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "GroundTruthError.h"
#include "RtabmapImpl.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/optimizer/Graph.h"

namespace rtabmap {
namespace {

// Error of a link against optimised poses, in standard deviations of the link (Mahalanobis
// distance of the translation and of the rotation under the link's information, the larger of
// the two). In 2D only x, y and yaw count.
double normalisedError(const Link& link, const std::map<int, Transform>& poses, bool is2D, double* metres) {
  const Transform& a = poses.at(link.from());
  const Transform& b = poses.at(link.to());
  const Transform e = link.transform().inverse() * (a.inverse() * b);
  Eigen::Vector3d t = e.translation();
  Eigen::Vector3d r;
  if (is2D) {
    t.z() = 0.0;
    r = Eigen::Vector3d(0.0, 0.0, e.theta());
  } else {
    const Eigen::AngleAxisd aa(e.rotationMatrix());
    r = aa.angle() * aa.axis();
  }
  if (metres) *metres = t.norm();
  const Link::InfMatrix& inf = link.infMatrix();
  const double chiT = std::sqrt(std::max(0.0, t.dot(inf.topLeftCorner<3, 3>() * t)));
  const double chiR = std::sqrt(std::max(0.0, r.dot(inf.bottomRightCorner<3, 3>() * r)));
  return std::max(chiT, chiR);
}

}  // namespace

std::map<int, Transform> Rtabmap::Impl::ramPosesOfGroup() const {
  const memory::Memory& memory = detector->memory();
  const std::set<int> maps = graph.mapsMergedWith(mapId);
  std::map<int, Transform> poses;
  auto add = [&](int id) {
    const Transform p = graph.pose(id);
    if (!p.isNull() && maps.count(graph.mapOf(id))) poses.emplace(id, p);
  };
  for (int id : memory.stm()) add(id);
  for (const auto& [id, age] : memory.wm()) {
    (void)age;
    add(id);
  }
  return poses;
}

std::multimap<int, Link> Rtabmap::Impl::ramLinks(const std::map<int, Transform>& poses) const {
  std::multimap<int, Link> links;
  for (const auto& [id, pose] : poses) {
    (void)pose;
    const Signature* s = detector->memory().signature(id);
    if (!s) continue;
    for (const auto& [to, link] : s->getLinks()) {
      // Each link once (from its smaller id); both ends must be in the local map. A node's
      // gravity link is its own (the optimiser uses it with Optimizer/GravitySigma), and so are
      // its landmark links (the landmark, id < 0, is placed by the optimiser).
      const bool kept = to == id  ? link.type() == Link::kGravity
                        : to < 0 ? link.type() == Link::kLandmark
                                 : to > id && poses.count(to) && link.type() != Link::kLandmark;
      if (kept) links.emplace_hint(links.end(), id, link);  // ids in increasing order
    }
  }
  return links;
}

// The graph was optimal before this update: started from its poses, the solver only has the new
// links' corrections to spread, a few iterations instead of a chordal relaxation of the whole
// local map each time. A large correction (a long loop, a merge of referentials) is where the
// poses can trap it in a local minimum: then Optimizer/Init decides, chordal by default.
OptimizerOptions Rtabmap::Impl::incrementalOptions(const std::map<int, Transform>& input,
                                                   const std::vector<Link>& newLinks) const {
  OptimizerOptions o = optimizer;
  bool large = false;
  for (const Link& l : newLinks) {
    // A landmark: where the graph had it, against where the new link puts it.
    const std::map<int, Transform>& ends = l.type() == Link::kLandmark ? landmarkPoses : input;
    auto a = input.find(l.from());
    auto b = ends.find(l.to());
    if (a == input.end() || b == ends.end()) continue;
    const Transform e = l.transform().inverse() * (a->second.inverse() * b->second);
    large = large || e.getNorm() > 0.2 || std::fabs(e.getAngle()) > 0.1;
  }
  if (!large) o.initialization = GraphInitialization::kInputPoses;
  return o;
}

std::vector<Link> Rtabmap::Impl::optimizeLocalMap(int newId, const std::vector<Link>& newLinks) {
  StageTimer timer(stats, Statistics::kTimingMap_optimization);
  const std::map<int, Transform> poses = ramPosesOfGroup();
  if (!poses.count(newId)) return newLinks;
  const std::multimap<int, Link> links = ramLinks(poses);
  // The optimiser keeps the new node's connected component (nodes in WM linked to the chain
  // only through the LTM stay where they are) and leaves the rest of the local map out.
  // RGBD/OptimizeFromGraphEnd: the robot stays, the map moves; else the component's oldest node
  // stays and map -> odom absorbs the correction.
  int root = newId;
  if (!options.optimizeFromGraphEnd) {
    const std::set<int> component = graph::connectedComponent(newId, links);
    root = *component.lower_bound(0);  // (landmarks, ids < 0, are no root)
  }
  OptimizerSummary result;
  const std::map<int, Transform> optimised =
      optimizeGraph(incrementalOptions(poses, newLinks), poses, links, &result, root);
  if (!result.success) {
    RTABMAP_WARN("graph optimisation failed: " << result.why << "; the new links are kept, the poses not updated");
    return newLinks;
  }
  stats.addStatistic(Statistics::kLoopOptimization_error, static_cast<float>(result.finalChi2));
  stats.addStatistic(Statistics::kLoopOptimization_iterations, static_cast<float>(result.iterations));

  // Every link counts, odometry included: a wrong loop closure made stiff by a confident
  // registration is satisfied by the optimiser, and it is the odometry that bends.
  double worst = 0.0, worstMetres = 0.0;
  for (const auto& [from, link] : links) {
    if (link.from() == link.to() || !optimised.count(link.from()) || !optimised.count(link.to()) ||
        link.type() == Link::kVirtualClosure) {
      continue;  // (gravity: the optimiser's own residual, not a motion between two poses)
    }
    double metres = 0.0;
    const double e = normalisedError(link, optimised, optimizer.force3DoF, &metres);
    if (e > worst) {
      worst = e;
      worstMetres = metres;
    }
  }
  stats.addStatistic(Statistics::kLoopOptimization_max_error, static_cast<float>(worstMetres));
  stats.addStatistic(Statistics::kLoopOptimization_max_error_ratio, static_cast<float>(worst));
  if (options.optimizeMaxError > 0.0f && worst > options.optimizeMaxError && !newLinks.empty()) {
    // The graph cannot hold the new links with what it already knows: one of them is wrong
    // (a false loop closure, a proximity link on an aliased corridor). Undo them.
    for (const Link& l : newLinks) {
      detector->memory().removeLink(l.from(), l.to(), l.type());
      detector->linksChanged({l.from(), l.to()});
      if (l.to() > 0) graph.unmergeMaps(graph.mapOf(l.from()), graph.mapOf(l.to()));  // (a landmark is in no map)
    }
    RTABMAP_WARN("rejected " << newLinks.size() << " new link(s) of node " << newId << ": after optimisation a link is off by "
                             << worst << " standard deviations (" << worstMetres << " m), more than "
                             << Parameters::kRGBDOptimizeMaxError() << " " << options.optimizeMaxError);
    return {};
  }
  std::map<int, Transform> nodes;
  for (const auto& [id, pose] : optimised) {
    if (id < 0) {
      landmarkPoses[id] = pose;  // the optimiser's estimate of each landmark of the local map
    } else {
      nodes.emplace(id, pose);
    }
  }
  graph.updatePoses(nodes);
  return newLinks;
}

void Rtabmap::Impl::retrieveNearRobot(const Transform& pose, memory::LoopClosureUpdate& u, std::set<int>& immune) {
  if (!db || options.maxLocalRetrieved <= 0 || pose.isNull()) return;
  memory::Memory& memory = detector->memory();
  std::map<int, Transform> inLtm;
  for (const auto& [id, p] : graph.posesOfGroup(mapId)) {
    if (!memory.inRam(id) && !memory.isIntermediate(id)) inLtm.emplace(id, p);  // locations only
  }
  if (inLtm.empty()) return;
  std::vector<int> wanted;
  for (const auto& [id, distance] : graph::findNearestNodes(inLtm, pose, options.maxLocalRetrieved, options.force3DoF)) {
    if (distance <= options.localRadius) wanted.push_back(id);
  }
  if (wanted.empty()) return;
  const std::vector<int> back = memory.retrieveIds(wanted);
  u.retrieved.insert(u.retrieved.end(), back.begin(), back.end());
  immune.insert(back.begin(), back.end());
}

// The local map near the robot stays in WM (nearest first), up to RGBD/LocalImmunizationRatio
// of WM: proximity detection needs it, and the robot is likely to need it next.
std::set<int> Rtabmap::Impl::localImmunity(const Transform& pose) const {
  std::set<int> immune;
  if (pose.isNull()) return immune;
  const memory::Memory& memory = detector->memory();
  const size_t maxImmune = static_cast<size_t>(options.localImmunizationRatio * static_cast<float>(memory.wmLocations()));
  if (maxImmune == 0) return immune;
  std::map<int, Transform> wmPoses;
  for (const auto& [id, p] : ramPosesOfGroup()) {
    if (memory.wm().count(id) && !memory.isIntermediate(id)) wmPoses.emplace(id, p);
  }
  for (const auto& [id, distance] :
       graph::findNearestNodes(wmPoses, pose, static_cast<int>(maxImmune), options.force3DoF)) {
    if (distance > options.localRadius) break;
    immune.insert(id);
  }
  return immune;
}

void Rtabmap::Impl::addGroundTruthStatistics(int nodeId) {
  if (!options.computeRmse || !options.metric) return;
  const memory::Memory& memory = detector->memory();
  const Signature* newest = memory.signature(nodeId);
  if (!newest || newest->getGroundTruthPose().isNull()) return;
  const std::map<int, Transform> poses = ramPosesOfGroup();
  std::map<int, Transform> truth;
  for (const auto& [id, pose] : poses) {
    (void)pose;
    const Signature* s = memory.signature(id);
    if (s && !s->getGroundTruthPose().isNull()) truth.emplace(id, s->getGroundTruthPose());
  }
  const std::optional<GroundTruthErrors> e = groundTruthErrors(poses, truth);
  if (!e) return;
  const struct {
    const char* name;
    const char* unit;
    const ErrorStats& s;
  } groups[] = {{"Translational", "/m", e->translational}, {"Rotational", "/deg", e->rotational}};
  for (const auto& g : groups) {
    const std::pair<const char*, double> values[] = {{"rmse", g.s.rmse}, {"mean", g.s.mean}, {"median", g.s.median},
                                                     {"std", g.s.std},   {"min", g.s.min},   {"max", g.s.max}};
    for (const auto& [what, value] : values) {
      stats.addStatistic(std::string("Gt/") + g.name + "_" + what + g.unit, static_cast<float>(value));
    }
  }
}

}  // namespace rtabmap

// Breadth-first spanning-tree initialisation of a pose graph.
#include <deque>
#include <unordered_map>
#include <vector>

#include "PoseMath.h"
#include "rtabmap_core/optimizer/Initialization.h"

namespace rtabmap::graph {

namespace {

struct Step {
  int next;
  const Link* link;
  bool forward;  // walking from link.from() to link.to()
};

bool isOdometry(Link::Type type) {
  return type == Link::kNeighbor || type == Link::kNeighborMerged;
}

// Poses are composed in plain Eigen (x, y, theta in 2D; rotation kept orthonormal through a
// normalised quaternion in 3D) and turned into Transforms once at the end.
struct Pose {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double yaw = 0.0;  // 2D
};

Pose fromTransform(const Transform& transform, bool is2D) {
  Pose p;
  if (is2D) {
    p.t = Eigen::Vector3d(transform.x(), transform.y(), 0.0);
    p.yaw = transform.yaw();
  } else {
    p.t = transform.translation();
    p.q = transform.quaternion().normalized();
  }
  return p;
}

Transform toTransform(const Pose& p, bool is2D) {
  if (is2D) return Transform(p.t.x(), p.t.y(), p.yaw);
  return Transform(p.t.x(), p.t.y(), p.t.z(), p.q.x(), p.q.y(), p.q.z(), p.q.w());
}

Pose compose(const Pose& a, const Pose& b, bool is2D) {
  Pose out;
  if (is2D) {
    const double c = std::cos(a.yaw), s = std::sin(a.yaw);
    out.t = Eigen::Vector3d(a.t.x() + c * b.t.x() - s * b.t.y(), a.t.y() + s * b.t.x() + c * b.t.y(), 0.0);
    out.yaw = optimizer_internal::wrapAngle(a.yaw + b.yaw);
  } else {
    out.t = a.t + a.q * b.t;
    out.q = (a.q * b.q).normalized();
  }
  return out;
}

Pose inverse(const Pose& p, bool is2D) {
  Pose out;
  if (is2D) {
    const double c = std::cos(p.yaw), s = std::sin(p.yaw);
    out.t = Eigen::Vector3d(-c * p.t.x() - s * p.t.y(), s * p.t.x() - c * p.t.y(), 0.0);
    out.yaw = -p.yaw;
  } else {
    out.q = p.q.conjugate();
    out.t = -(out.q * p.t);
  }
  return out;
}

}  // namespace

std::map<int, Transform> spanningTreeInitialization(int root, const Transform& rootPose,
                                                    const std::multimap<int, Link>& links,
                                                    bool is2D, bool odometryFirst,
                                                    const std::map<int, Transform>* known) {
  std::unordered_map<int, std::vector<Step>> adj;
  for (const auto& [key, link] : links) {
    (void)key;
    if (link.from() == link.to() || link.transform().isNull()) continue;
    adj[link.from()].push_back({link.to(), &link, true});
    adj[link.to()].push_back({link.from(), &link, false});
  }

  auto knownPose = [&](int id) -> const Transform* {
    if (!known) return nullptr;
    const auto it = known->find(id);
    return (it != known->end() && !it->second.isNull()) ? &it->second : nullptr;
  };

  std::unordered_map<int, Pose> placed;
  std::vector<int> order;  // placement order
  const Transform* rootKnown = knownPose(root);
  const Transform start = rootKnown ? *rootKnown : (rootPose.isNull() ? Transform::Identity() : rootPose);
  placed.emplace(root, fromTransform(start, is2D));
  order.push_back(root);

  // One breadth-first pass from every node already placed, along odometry links only or all.
  auto grow = [&](bool onlyOdometry) {
    std::deque<int> queue(order.begin(), order.end());
    while (!queue.empty()) {
      const int id = queue.front();
      queue.pop_front();
      const auto it = adj.find(id);
      if (it == adj.end()) continue;
      const Pose pose = placed.at(id);
      for (const Step& step : it->second) {
        if (onlyOdometry && !isOdometry(step.link->type())) continue;
        if (placed.count(step.next)) continue;
        Pose next;
        if (const Transform* given = knownPose(step.next)) {
          next = fromTransform(*given, is2D);
        } else {
          const Pose z = fromTransform(step.link->transform(), is2D);
          next = compose(pose, step.forward ? z : inverse(z, is2D), is2D);
        }
        placed.emplace(step.next, next);
        order.push_back(step.next);
        queue.push_back(step.next);
      }
    }
  };
  if (odometryFirst) grow(true);
  grow(false);

  std::map<int, Transform> poses;
  for (const auto& [id, p] : placed) poses.emplace(id, toTransform(p, is2D));
  return poses;
}

// The SLAM update initialises from the poses it has at every optimisation of the local map,
// where building the tree's adjacency and walking it was a tenth of the optimisation.
std::map<int, Transform> knownPosesInitialization(const std::set<int>& nodes,
                                                  const std::map<int, Transform>& known, bool is2D) {
  std::map<int, Transform> poses;
  auto k = known.begin();
  for (int id : nodes) {  // both sorted: one merge pass
    while (k != known.end() && k->first < id) ++k;
    if (k == known.end() || k->first != id || k->second.isNull()) return {};
    poses.emplace_hint(poses.end(), id, toTransform(fromTransform(k->second, is2D), is2D));
  }
  return poses;
}

}  // namespace rtabmap::graph

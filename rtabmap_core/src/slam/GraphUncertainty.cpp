#include "GraphUncertainty.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <vector>

namespace rtabmap {
namespace {

// A node reached from the root: its pose (x, y, theta) in the root's frame and the covariance of
// that pose, both compounded along the chain that reached it.
struct Reached {
  Eigen::Vector3d pose = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

// Largest eigenvalue of the position block: the variance along the most uncertain direction.
double positionVariance(const Eigen::Matrix3d& c) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(c.topLeftCorner<2, 2>());
  return std::max(0.0, solver.eigenvalues()(1));
}

// Covariance of (x, y, yaw) of a link in its `from` frame: the marginal of the inverse of its
// 6x6 information matrix. False when the link carries no usable information.
bool planarCovariance(const Link& link, Eigen::Matrix3d* out) {
  const Link::InfMatrix& info = link.infMatrix();
  if (!info.allFinite()) return false;
  const Eigen::FullPivLU<Link::InfMatrix> lu(info);
  if (!lu.isInvertible()) return false;
  const Eigen::Matrix<double, 6, 6> cov = lu.inverse();
  const int idx[3] = {0, 1, 5};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) (*out)(r, c) = cov(idx[r], idx[c]);
  }
  return out->allFinite() && (*out)(0, 0) >= 0.0 && (*out)(1, 1) >= 0.0 && (*out)(2, 2) >= 0.0;
}

// `from` followed by `link` (Smith, Self & Cheeseman's compounding): the position of the next
// node moves with the heading error of `from` by the lever arm of the link's translation (in the
// root frame, hence rotation variance x lever arm squared, with its correlations), and gains the
// link's own covariance rotated into the root frame.
Reached compound(const Reached& from, const Link& link, const Eigen::Matrix3d& linkCovariance) {
  const double c = std::cos(from.pose.z()), s = std::sin(from.pose.z());
  const Transform& t = link.transform();
  const Eigen::Vector2d step(c * t.x() - s * t.y(), s * t.x() + c * t.y());  // in the root frame
  Eigen::Matrix3d j = Eigen::Matrix3d::Identity();                          // d next / d from
  j(0, 2) = -step.y();
  j(1, 2) = step.x();
  Eigen::Matrix3d g = Eigen::Matrix3d::Identity();  // d next / d link (link in from's frame)
  g(0, 0) = c;
  g(0, 1) = -s;
  g(1, 0) = s;
  g(1, 1) = c;
  Reached next;
  next.pose = Eigen::Vector3d(from.pose.x() + step.x(), from.pose.y() + step.y(), from.pose.z() + t.theta());
  next.covariance = j * from.covariance * j.transpose() + g * linkCovariance * g.transpose();
  next.covariance = 0.5 * (next.covariance + next.covariance.transpose());
  return next;
}

}  // namespace

std::map<int, double> graphPositionSigmas(int root, double limit,
                                          const std::function<const std::multimap<int, Link>*(int)>& linksOf) {
  // Dijkstra on the position variance (trace). Each link adds its own covariance, but the
  // heading's lever arm can shift variance between directions, so the order is a heuristic: the
  // chain kept for a node is the least uncertain one found, not provably the least of all.
  const double limitVariance = limit * limit;
  std::map<int, Reached> reached{{root, Reached()}};
  std::map<int, double> cost{{root, 0.0}};
  std::map<int, double> sigmas;
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  open.emplace(0.0, root);
  while (!open.empty()) {
    const auto [d, id] = open.top();
    open.pop();
    if (sigmas.count(id) || d > cost[id]) continue;
    const Reached here = reached.at(id);
    sigmas[id] = std::sqrt(positionVariance(here.covariance));
    const std::multimap<int, Link>* links = linksOf(id);
    if (!links) continue;
    for (const auto& [to, link] : *links) {
      if (to == id || sigmas.count(to) || link.type() == Link::kVirtualClosure || link.transform().isNull()) continue;
      Eigen::Matrix3d linkCovariance;
      if (!planarCovariance(link, &linkCovariance)) continue;
      const Reached next = compound(here, link, linkCovariance);
      if (positionVariance(next.covariance) > limitVariance) continue;
      const double nextCost = next.covariance(0, 0) + next.covariance(1, 1);
      const auto it = cost.find(to);
      if (it != cost.end() && it->second <= nextCost) continue;
      cost[to] = nextCost;
      reached[to] = next;
      open.emplace(nextCost, to);
    }
  }
  return sigmas;
}

float correlativeWindowFor(double sigma, float window, float icpReach, float sigmas) {
  if (sigmas <= 0.0f || !(sigma < std::numeric_limits<double>::infinity())) return window;
  return std::min(window, std::max(icpReach, sigmas * static_cast<float>(sigma)));
}

}  // namespace rtabmap

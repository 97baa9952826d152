#include "rtabmap_core/eval/PathDeviation.h"

#include <flann/flann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {
namespace {

std::vector<Eigen::Vector3d> positionsOf(const Trajectory& t, std::vector<size_t>* indices) {
  std::vector<Eigen::Vector3d> out;
  for (size_t i = 0; i < t.size(); ++i) {
    const Transform& p = t[i].pose;
    if (p.isNull()) continue;
    out.emplace_back(p.x(), p.y(), p.z());
    if (indices) indices->push_back(i);
  }
  return out;
}

Transform firstNonNull(const Trajectory& t) {
  for (const StampedPose& p : t.poses) {
    if (!p.pose.isNull()) return p.pose;
  }
  return Transform();
}

double distanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         Eigen::Vector3d* nearest) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  *nearest = a + s * ab;
  return (p - *nearest).norm();
}

// The reference polyline, sampled along its segments for a kd-tree that finds the segment
// nearest to a point; the distance is then computed exactly to that segment and its neighbours.
class Polyline {
 public:
  Polyline(std::vector<Eigen::Vector3d> vertices, double step) : vertices_(std::move(vertices)) {
    for (size_t s = 0; s + 1 < vertices_.size(); ++s) {
      const Eigen::Vector3d& a = vertices_[s];
      const Eigen::Vector3d& b = vertices_[s + 1];
      const double len = (b - a).norm();
      length_ += len;
      const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
      for (int k = 0; k < n; ++k) addSample(a + (b - a) * (static_cast<double>(k) / n), s);
    }
    addSample(vertices_.back(), vertices_.size() - 2);
    const flann::Matrix<double> m(samples_.data(), sampleSegment_.size(), 3);
    index_ = std::make_unique<flann::KDTreeSingleIndex<flann::L2_Simple<double>>>(m, flann::KDTreeSingleIndexParams(10));
    index_->buildIndex();
  }

  double length() const { return length_; }

  // Distance from p to the polyline, and its nearest point there.
  double distance(const Eigen::Vector3d& p, Eigen::Vector3d* nearest) const {
    double query[3] = {p.x(), p.y(), p.z()};
    int index = 0;
    double d2 = 0.0;
    flann::Matrix<double> q(query, 1, 3);
    flann::Matrix<int> indices(&index, 1, 1);
    flann::Matrix<double> distances(&d2, 1, 1);
    index_->knnSearch(q, indices, distances, 1, flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED, 0.0f, false));
    const size_t segment = sampleSegment_[static_cast<size_t>(index)];
    double best = std::numeric_limits<double>::infinity();
    const size_t first = segment > 0 ? segment - 1 : 0;
    const size_t last = std::min(segment + 1, vertices_.size() - 2);
    for (size_t s = first; s <= last; ++s) {
      Eigen::Vector3d onSegment;
      const double d = distanceToSegment(p, vertices_[s], vertices_[s + 1], &onSegment);
      if (d < best) {
        best = d;
        *nearest = onSegment;
      }
    }
    return best;
  }

 private:
  void addSample(const Eigen::Vector3d& p, size_t segment) {
    samples_.insert(samples_.end(), {p.x(), p.y(), p.z()});
    sampleSegment_.push_back(segment);
  }

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<double> samples_;        // x y z per sample
  std::vector<size_t> sampleSegment_;  // the segment each sample lies on
  std::unique_ptr<flann::KDTreeSingleIndex<flann::L2_Simple<double>>> index_;
  double length_ = 0.0;
};

}  // namespace

PathDeviationResult computePathDeviation(const Trajectory& reference, const Trajectory& estimate,
                                         const PathDeviationOptions& options) {
  PathDeviationResult r;
  std::vector<Eigen::Vector3d> ref = positionsOf(reference, nullptr);
  const std::vector<Eigen::Vector3d> est = positionsOf(estimate, &r.estimateIndices);
  r.referencePoses = ref.size();
  r.estimatedPoses = est.size();
  if (ref.size() < 2) {
    throw FormatError("path deviation: the reference has " + std::to_string(ref.size()) +
                      " non-null poses, a path needs 2");
  }
  if (est.size() < 3) {
    throw FormatError("path deviation: the estimate has " + std::to_string(est.size()) +
                      " non-null poses, the alignment needs 3");
  }
  const Polyline path(std::move(ref), options.sampleStep > 0.0 ? options.sampleStep : 0.02);
  r.referenceLength = path.length();

  Transform alignment = Transform::Identity();
  if (options.initFromFirstPoses) alignment = firstNonNull(reference) * firstNonNull(estimate).inverse();
  std::vector<double> distances(est.size());
  std::vector<Eigen::Vector3d> aligned(est.size()), nearest(est.size());
  auto pairUp = [&](const Transform& t) {
    for (size_t i = 0; i < est.size(); ++i) {
      aligned[i] = t * est[i];
      distances[i] = path.distance(aligned[i], &nearest[i]);
    }
  };
  for (r.iterations = 0; r.iterations < options.maxIterations && !r.converged; ++r.iterations) {
    pairUp(alignment);
    const double trim = std::max(options.trimDistance, percentile(distances, options.trimQuantile));
    std::vector<Eigen::Vector3d> source, target;
    for (size_t i = 0; i < est.size(); ++i) {
      if (distances[i] > trim) continue;
      source.push_back(aligned[i]);
      target.push_back(nearest[i]);
    }
    if (source.size() < 3) break;  // nothing left to fit: keep the alignment as it is
    const Transform step = alignPoints(source, target, false);
    alignment = step * alignment;
    r.converged = step.getNorm() < options.convergence && step.getAngle() < options.convergence;
  }
  pairUp(alignment);
  r.alignment = alignment;
  r.deviations = distances;
  r.stats = computeErrorStats(distances);
  r.p90 = percentile(distances, 0.9);
  r.p99 = percentile(distances, 0.99);
  return r;
}

}  // namespace rtabmap

#include "rtabmap_core/eval/TrajectoryError.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <tuple>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

std::vector<size_t> stampOrder(const Trajectory& t) {
  std::vector<size_t> order(t.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&t](size_t a, size_t b) { return t.poses[a].stamp < t.poses[b].stamp; });
  return order;
}

std::string stampRange(const Trajectory& t) {
  if (t.empty()) return "no pose";
  double lo = t.poses.front().stamp, hi = lo;
  for (const auto& p : t.poses) {
    lo = std::min(lo, p.stamp);
    hi = std::max(hi, p.stamp);
  }
  std::ostringstream s;
  s.precision(17);
  s << t.size() << " poses, stamps " << lo << " .. " << hi;
  return s.str();
}

}  // namespace

ErrorStats computeErrorStats(const std::vector<double>& values) {
  ErrorStats s;
  s.count = values.size();
  if (values.empty()) return s;
  double sum = 0.0, sumSq = 0.0;
  for (double v : values) {
    sum += v;
    sumSq += v * v;
  }
  const double n = static_cast<double>(values.size());
  s.mean = sum / n;
  s.rmse = std::sqrt(sumSq / n);
  double var = 0.0;
  for (double v : values) var += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(var / n);
  std::vector<double> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  s.min = sorted.front();
  s.max = sorted.back();
  const size_t m = sorted.size() / 2;
  s.median = sorted.size() % 2 ? sorted[m] : 0.5 * (sorted[m - 1] + sorted[m]);
  return s;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  const double clamped = std::min(1.0, std::max(0.0, p));
  const size_t i = static_cast<size_t>(std::lround(clamped * static_cast<double>(values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + static_cast<long>(i), values.end());
  return values[i];
}

std::vector<std::pair<size_t, size_t>> associateByStamp(const Trajectory& a, const Trajectory& b,
                                                        double maxDifference) {
  const std::vector<size_t> oa = stampOrder(a);
  const std::vector<size_t> ob = stampOrder(b);
  // Candidate pairs within maxDifference (a sliding window over b's sorted stamps).
  std::vector<std::tuple<double, size_t, size_t>> candidates;  // diff, rank in a, rank in b
  size_t lo = 0;
  for (size_t ra = 0; ra < oa.size(); ++ra) {
    const StampedPose& pa = a.poses[oa[ra]];
    if (pa.pose.isNull()) continue;
    while (lo < ob.size() && b.poses[ob[lo]].stamp < pa.stamp - maxDifference) ++lo;
    for (size_t rb = lo; rb < ob.size() && b.poses[ob[rb]].stamp <= pa.stamp + maxDifference; ++rb) {
      const StampedPose& pb = b.poses[ob[rb]];
      if (pb.pose.isNull()) continue;
      candidates.emplace_back(std::abs(pa.stamp - pb.stamp), ra, rb);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<char> usedA(oa.size(), 0), usedB(ob.size(), 0);
  std::vector<std::pair<size_t, size_t>> ranks;
  for (const auto& [diff, ra, rb] : candidates) {
    if (usedA[ra] || usedB[rb]) continue;
    usedA[ra] = usedB[rb] = 1;
    ranks.emplace_back(ra, rb);
  }
  std::sort(ranks.begin(), ranks.end());
  std::vector<std::pair<size_t, size_t>> pairs;
  pairs.reserve(ranks.size());
  for (const auto& [ra, rb] : ranks) pairs.emplace_back(oa[ra], ob[rb]);
  return pairs;
}

Transform alignPoints(const std::vector<Eigen::Vector3d>& source,
                      const std::vector<Eigen::Vector3d>& target, bool withScale, double* scale) {
  if (source.size() != target.size()) {
    throw FormatError("alignPoints: " + std::to_string(source.size()) + " source points for " +
                      std::to_string(target.size()) + " target points");
  }
  if (source.size() < 3) {
    throw FormatError("alignment needs at least 3 associated poses, got " + std::to_string(source.size()));
  }
  const Eigen::Index n = static_cast<Eigen::Index>(source.size());
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < n; ++i) {
    src.col(i) = source[static_cast<size_t>(i)];
    dst.col(i) = target[static_cast<size_t>(i)];
    mean += source[static_cast<size_t>(i)];
  }
  mean /= static_cast<double>(n);
  double spread = 0.0;
  for (const auto& p : source) spread += (p - mean).squaredNorm();
  if (spread / static_cast<double>(n) < 1e-18) {
    throw FormatError("alignment: the estimated positions are all the same point (no motion): "
                      "nothing to align");
  }
  const Eigen::Matrix4d m = Eigen::umeyama(src, dst, withScale);
  Eigen::Matrix3d sR = m.topLeftCorner<3, 3>();
  // Columns of s R all have norm s.
  const double s = withScale ? sR.col(0).norm() : 1.0;
  Eigen::Matrix4d rigid = Eigen::Matrix4d::Identity();
  rigid.topLeftCorner<3, 3>() = sR / s;
  rigid.topRightCorner<3, 1>() = m.topRightCorner<3, 1>();
  if (scale) *scale = s;
  return Transform(rigid);
}

AteResult computeAte(const Trajectory& groundTruth, const Trajectory& estimate, const AteOptions& options) {
  AteResult r;
  r.groundTruthPoses = groundTruth.size();
  r.estimatedPoses = estimate.size();
  r.pairs = associateByStamp(groundTruth, estimate, options.maxTimeDifference);
  const size_t needed = options.alignment == TrajectoryAlignment::kNone ? 1 : 3;
  if (r.pairs.size() < needed) {
    std::ostringstream s;
    s << "ATE: " << r.pairs.size() << " poses associated within " << options.maxTimeDifference
      << " s, at least " << needed << " needed (ground truth: " << stampRange(groundTruth)
      << "; estimate: " << stampRange(estimate) << ")";
    throw FormatError(s.str());
  }
  std::vector<Eigen::Vector3d> gt, est;
  for (const auto& [i, j] : r.pairs) {
    gt.push_back(groundTruth.poses[i].pose.translation());
    est.push_back(estimate.poses[j].pose.translation());
  }
  if (options.alignment != TrajectoryAlignment::kNone) {
    r.alignment = alignPoints(est, gt, options.alignment == TrajectoryAlignment::kSim3, &r.scale);
  }
  const Eigen::Matrix3d R = r.alignment.rotationMatrix();
  const Eigen::Vector3d t = r.alignment.translation();
  r.errors.reserve(gt.size());
  for (size_t k = 0; k < gt.size(); ++k) {
    r.errors.push_back((gt[k] - (r.scale * (R * est[k]) + t)).norm());
  }
  r.translation = computeErrorStats(r.errors);
  return r;
}

Trajectory applyAlignment(const Trajectory& estimate, const Transform& alignment, double scale) {
  Trajectory out;
  out.poses.reserve(estimate.size());
  for (const auto& p : estimate.poses) {
    if (p.pose.isNull()) {
      out.add(p.stamp, p.pose);
      continue;
    }
    Eigen::Isometry3d scaled = p.pose.toEigen();
    scaled.translation() *= scale;
    out.add(p.stamp, alignment * Transform(scaled));
  }
  return out;
}

RpeResult computeRpe(const Trajectory& groundTruth, const Trajectory& estimate, const RpeOptions& options) {
  if (!(options.delta > 0.0)) throw FormatError("RPE: delta must be positive");
  const auto pairs = associateByStamp(groundTruth, estimate, options.maxTimeDifference);
  RpeResult r;
  r.associated = pairs.size();
  std::vector<Transform> gt, est;
  for (const auto& [i, j] : pairs) {
    gt.push_back(groundTruth.poses[i].pose);
    est.push_back(estimate.poses[j].pose);
  }
  std::vector<double> trans, rot;
  auto addPair = [&](size_t k, size_t j) {
    const Transform e = (gt[k].inverse() * gt[j]).inverse() * (est[k].inverse() * est[j]);
    trans.push_back(e.getNorm());
    rot.push_back(e.getAngle() * kRadToDeg);
  };
  if (options.unit == RpeOptions::Unit::kFrames) {
    const double rounded = std::round(options.delta);
    if (rounded < 1.0 || std::abs(rounded - options.delta) > 1e-9) {
      throw FormatError("RPE per frame: delta must be a whole number of frames >= 1");
    }
    const size_t d = static_cast<size_t>(rounded);
    for (size_t k = 0; k + d < gt.size(); ++k) addPair(k, k + d);
  } else {
    std::vector<double> dist(gt.size(), 0.0);
    for (size_t k = 1; k < gt.size(); ++k) {
      dist[k] = dist[k - 1] + (gt[k].translation() - gt[k - 1].translation()).norm();
    }
    for (size_t k = 0; k < gt.size(); ++k) {
      const auto it = std::lower_bound(dist.begin() + static_cast<long>(k), dist.end(), dist[k] + options.delta);
      if (it == dist.end()) break;
      addPair(k, static_cast<size_t>(it - dist.begin()));
    }
  }
  if (trans.empty()) {
    std::ostringstream s;
    s << "RPE: no pose pair " << options.delta
      << (options.unit == RpeOptions::Unit::kFrames ? " frames" : " m") << " apart among the "
      << pairs.size() << " associated poses (ground truth: " << stampRange(groundTruth)
      << "; estimate: " << stampRange(estimate) << ")";
    throw FormatError(s.str());
  }
  r.translation = computeErrorStats(trans);
  r.rotation = computeErrorStats(rot);
  return r;
}

KittiResult computeKittiError(const std::vector<Transform>& groundTruth,
                              const std::vector<Transform>& estimate, const KittiOptions& options) {
  if (groundTruth.size() != estimate.size()) {
    throw FormatError("KITTI error: " + std::to_string(groundTruth.size()) + " ground-truth poses for " +
                      std::to_string(estimate.size()) + " estimated poses (one per frame each expected)");
  }
  for (size_t i = 0; i < groundTruth.size(); ++i) {
    if (groundTruth[i].isNull() || estimate[i].isNull()) {
      throw FormatError("KITTI error: frame " + std::to_string(i) + " has no pose");
    }
  }
  if (options.stepSize == 0) throw FormatError("KITTI error: step size must be >= 1");
  KittiResult r;
  r.frames = groundTruth.size();
  std::vector<double> dist(groundTruth.size(), 0.0);
  for (size_t i = 1; i < groundTruth.size(); ++i) {
    dist[i] = dist[i - 1] + (groundTruth[i].translation() - groundTruth[i - 1].translation()).norm();
  }
  std::vector<double> tSum(options.lengths.size(), 0.0), rSum(options.lengths.size(), 0.0);
  std::vector<size_t> counts(options.lengths.size(), 0);
  double tTotal = 0.0, rTotal = 0.0;
  for (size_t first = 0; first < groundTruth.size(); first += options.stepSize) {
    for (size_t li = 0; li < options.lengths.size(); ++li) {
      const double len = options.lengths[li];
      // The first frame farther than len along the path (the devkit's
      // lastFrameFromSegmentLength: dist[i] > dist[first] + len).
      const auto it = std::upper_bound(dist.begin() + static_cast<long>(first), dist.end(), dist[first] + len);
      if (it == dist.end()) continue;
      const size_t last = static_cast<size_t>(it - dist.begin());
      const Transform deltaGt = groundTruth[first].inverse() * groundTruth[last];
      const Transform deltaEst = estimate[first].inverse() * estimate[last];
      const Transform error = deltaEst.inverse() * deltaGt;
      const double tErr = error.getNorm() / len;
      const double rErr = error.getAngle() / len;
      tSum[li] += tErr;
      rSum[li] += rErr;
      ++counts[li];
      tTotal += tErr;
      rTotal += rErr;
      ++r.segments;
    }
  }
  if (r.segments == 0) {
    const double shortest = options.lengths.empty() ? 0.0 : *std::min_element(options.lengths.begin(), options.lengths.end());
    std::ostringstream s;
    s << "KITTI error: the ground-truth path is " << dist.back()
      << " m long, no sub-sequence of " << shortest << " m or more fits in it";
    throw FormatError(s.str());
  }
  r.translationPercent = 100.0 * tTotal / static_cast<double>(r.segments);
  r.rotationDegPerMetre = kRadToDeg * rTotal / static_cast<double>(r.segments);
  for (size_t li = 0; li < options.lengths.size(); ++li) {
    if (counts[li] == 0) continue;
    KittiLengthError e;
    e.length = options.lengths[li];
    e.segments = counts[li];
    e.translationPercent = 100.0 * tSum[li] / static_cast<double>(counts[li]);
    e.rotationDegPerMetre = kRadToDeg * rSum[li] / static_cast<double>(counts[li]);
    r.perLength.push_back(e);
  }
  return r;
}

}  // namespace rtabmap

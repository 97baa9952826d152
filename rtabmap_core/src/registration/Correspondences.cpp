#include "rtabmap_core/registration/Correspondences.h"

#include <opencv2/features2d.hpp>
#include <opencv2/flann.hpp>
#include <opencv2/video/tracking.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "DescriptorDistance.h"

namespace rtabmap {

using registration_detail::descriptorDistance;

CorrespondenceOptions CorrespondenceOptions::fromParameters(const ParametersMap& p) {
  CorrespondenceOptions o;
  o.type = Parameters::getInt(p, Parameters::kVisCorType());
  o.nnType = static_cast<NearestNeighborType>(Parameters::getInt(p, Parameters::kVisCorNNType()));
  o.nndr = Parameters::getFloat(p, Parameters::kVisCorNNDR());
  o.guessWinSize = Parameters::getInt(p, Parameters::kVisCorGuessWinSize());
  o.guessMatchToProjection = Parameters::getBool(p, Parameters::kVisCorGuessMatchToProjection());
  o.flowWinSize = Parameters::getInt(p, Parameters::kVisCorFlowWinSize());
  o.flowIterations = Parameters::getInt(p, Parameters::kVisCorFlowIterations());
  o.flowEps = Parameters::getFloat(p, Parameters::kVisCorFlowEps());
  o.flowMaxLevel = Parameters::getInt(p, Parameters::kVisCorFlowMaxLevel());
  return o;
}

bool CorrespondenceOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (type != 0 && type != 1) return fail("Vis/CorType must be 0 (features matching) or 1 (optical flow)");
  switch (nnType) {
    case NearestNeighborType::kFlannLinear: case NearestNeighborType::kFlannKdTree: case NearestNeighborType::kFlannLsh:
    case NearestNeighborType::kBruteForce: case NearestNeighborType::kBruteForceCrossCheck:
      break;
    default:
      return fail("Vis/CorNNType " + std::to_string(static_cast<int>(nnType)) + " is not available");
  }
  if (!(nndr > 0.0f && nndr <= 1.0f)) return fail("Vis/CorNNDR must be in (0, 1]");
  if (guessWinSize < 0) return fail("Vis/CorGuessWinSize must not be negative");
  if (flowWinSize < 3) return fail("Vis/CorFlowWinSize must be at least 3 for Lucas-Kanade");
  if (flowIterations < 1) return fail("Vis/CorFlowIterations must be at least 1");
  if (!(flowEps > 0.0f)) return fail("Vis/CorFlowEps must be positive");
  if (flowMaxLevel < 0) return fail("Vis/CorFlowMaxLevel must not be negative");
  if (flowBackCheck < 0.0f) return fail("the optical flow forward-backward bound must not be negative");
  return true;
}

NearestNeighborType effectiveNearestNeighborType(NearestNeighborType requested, bool binary) {
  if (binary && (requested == NearestNeighborType::kFlannKdTree || requested == NearestNeighborType::kFlannLinear)) {
    return NearestNeighborType::kBruteForce;
  }
  if (!binary && requested == NearestNeighborType::kFlannLsh) return NearestNeighborType::kFlannKdTree;
  if (!binary && requested == NearestNeighborType::kFlannLinear) return NearestNeighborType::kBruteForce;
  return requested;
}

namespace {

// Keeps, for each `from` feature claimed by several matches, the closest one.
std::vector<cv::DMatch> uniqueOnQuery(const std::vector<cv::DMatch>& matches) {
  std::unordered_map<int, size_t> best;
  for (size_t i = 0; i < matches.size(); ++i) {
    auto it = best.find(matches[i].queryIdx);
    if (it == best.end()) {
      best.emplace(matches[i].queryIdx, i);
    } else if (matches[i].distance < matches[it->second].distance) {
      it->second = i;
    }
  }
  std::vector<cv::DMatch> out;
  out.reserve(best.size());
  for (size_t i = 0; i < matches.size(); ++i) {
    auto it = best.find(matches[i].queryIdx);
    if (it->second == i) out.push_back(matches[i]);
  }
  return out;
}

cv::Ptr<cv::DescriptorMatcher> makeMatcher(NearestNeighborType type, bool binary) {
  switch (type) {
    case NearestNeighborType::kFlannKdTree:
      return cv::makePtr<cv::FlannBasedMatcher>(cv::makePtr<cv::flann::KDTreeIndexParams>(4),
                                                cv::makePtr<cv::flann::SearchParams>(32));
    case NearestNeighborType::kFlannLsh:
      return cv::makePtr<cv::FlannBasedMatcher>(cv::makePtr<cv::flann::LshIndexParams>(12, 20, 2));
    case NearestNeighborType::kBruteForceCrossCheck:
      return cv::BFMatcher::create(binary ? cv::NORM_HAMMING : cv::NORM_L2, true);
    default:
      return cv::BFMatcher::create(binary ? cv::NORM_HAMMING : cv::NORM_L2, false);
  }
}

// Largest Hamming distance accepted for a lone candidate in a guided-matching window, as a
// fraction of the descriptor's bits: unrelated binary descriptors differ in about half their
// bits, repeated views of a corner in well under a third.
constexpr float kLoneBinaryMaxRatio = 0.3f;

}  // namespace

std::vector<cv::DMatch> matchDescriptors(const cv::Mat& fromDescriptors, const cv::Mat& toDescriptors,
                                         const CorrespondenceOptions& options) {
  std::vector<cv::DMatch> matches;
  if (fromDescriptors.empty() || toDescriptors.empty()) return matches;
  if (fromDescriptors.type() != toDescriptors.type() || fromDescriptors.cols != toDescriptors.cols) {
    throw std::invalid_argument("matchDescriptors: descriptors of different types or lengths");
  }
  const bool binary = fromDescriptors.type() == CV_8U;
  const NearestNeighborType type = effectiveNearestNeighborType(options.nnType, binary);
  cv::Ptr<cv::DescriptorMatcher> matcher = makeMatcher(type, binary);
  if (type == NearestNeighborType::kBruteForceCrossCheck) {
    std::vector<cv::DMatch> raw;
    matcher->match(toDescriptors, fromDescriptors, raw);
    for (const cv::DMatch& m : raw) matches.emplace_back(m.trainIdx, m.queryIdx, m.distance);
    return uniqueOnQuery(matches);
  }
  if (fromDescriptors.rows < 2) return matches;  // no second neighbour for the ratio test
  std::vector<std::vector<cv::DMatch>> knn;
  matcher->knnMatch(toDescriptors, fromDescriptors, knn, 2);
  for (const auto& k : knn) {
    if (k.size() < 2) continue;
    if (k[0].distance < options.nndr * k[1].distance) matches.emplace_back(k[0].trainIdx, k[0].queryIdx, k[0].distance);
  }
  return uniqueOnQuery(matches);
}

namespace {

// Points of one side bucketed on a grid of `radius`-sized cells, for window queries.
class PointGrid {
 public:
  PointGrid(const std::vector<cv::Point2f>& points, float radius) : points_(points), cell_(std::max(1.0f, radius)) {
    for (size_t i = 0; i < points.size(); ++i) {
      if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y)) continue;
      cells_[key(cellOf(points[i].x), cellOf(points[i].y))].push_back(static_cast<int>(i));
    }
  }
  // Indices of points within radius of p.
  void query(const cv::Point2f& p, float radius, std::vector<int>& out) const {
    out.clear();
    const int cx = cellOf(p.x), cy = cellOf(p.y);
    const float r2 = radius * radius;
    for (int y = cy - 1; y <= cy + 1; ++y) {
      for (int x = cx - 1; x <= cx + 1; ++x) {
        auto it = cells_.find(key(x, y));
        if (it == cells_.end()) continue;
        for (int i : it->second) {
          const float dx = points_[static_cast<size_t>(i)].x - p.x;
          const float dy = points_[static_cast<size_t>(i)].y - p.y;
          if (dx * dx + dy * dy <= r2) out.push_back(i);
        }
      }
    }
  }

 private:
  int cellOf(float v) const { return static_cast<int>(std::floor(v / cell_)); }
  // Shift the unsigned image of x: a negative x shifted left is undefined before C++20.
  static long long key(int x, int y) {
    return static_cast<long long>(static_cast<unsigned long long>(static_cast<long long>(x)) << 32) ^
           static_cast<unsigned int>(y);
  }
  const std::vector<cv::Point2f>& points_;
  float cell_;
  std::unordered_map<long long, std::vector<int>> cells_;
};

// Nearest candidate of descriptor `row` of `A` among rows `candidates` of `B`, with the ratio
// test (or the lone-candidate bound). Returns the index in B or -1.
int bestCandidate(const cv::Mat& A, int row, const cv::Mat& B, const std::vector<int>& candidates, float nndr,
                  float& distance) {
  float best = std::numeric_limits<float>::max(), second = std::numeric_limits<float>::max();
  int bestIndex = -1;
  for (int c : candidates) {
    const float d = descriptorDistance(A, row, B, c);
    if (d < best) {
      second = best;
      best = d;
      bestIndex = c;
    } else if (d < second) {
      second = d;
    }
  }
  if (bestIndex < 0) return -1;
  distance = best;
  if (candidates.size() == 1) {
    if (A.type() == CV_8U && best > kLoneBinaryMaxRatio * static_cast<float>(A.cols * 8)) return -1;
    return bestIndex;
  }
  return best < nndr * second ? bestIndex : -1;
}

}  // namespace

std::vector<cv::DMatch> matchByProjection(const std::vector<cv::Point2f>& projected, const cv::Mat& fromDescriptors,
                                          const std::vector<cv::KeyPoint>& toKeypoints, const cv::Mat& toDescriptors,
                                          float radius, const CorrespondenceOptions& options) {
  std::vector<cv::DMatch> matches;
  if (projected.empty() || toKeypoints.empty() || fromDescriptors.empty() || toDescriptors.empty()) return matches;
  if (fromDescriptors.type() != toDescriptors.type() || fromDescriptors.cols != toDescriptors.cols) {
    throw std::invalid_argument("matchByProjection: descriptors of different types or lengths");
  }
  if (static_cast<int>(projected.size()) != fromDescriptors.rows ||
      static_cast<int>(toKeypoints.size()) != toDescriptors.rows) {
    throw std::invalid_argument("matchByProjection: one descriptor row per point expected");
  }
  std::vector<cv::Point2f> toPoints;
  cv::KeyPoint::convert(toKeypoints, toPoints);
  std::vector<int> candidates;
  if (!options.guessMatchToProjection) {
    const PointGrid grid(toPoints, radius);
    std::vector<int> claimedBy(toPoints.size(), -1);  // best match index per `to` keypoint
    for (size_t i = 0; i < projected.size(); ++i) {
      if (!std::isfinite(projected[i].x) || !std::isfinite(projected[i].y)) continue;
      grid.query(projected[i], radius, candidates);
      float d = 0.0f;
      const int j = bestCandidate(fromDescriptors, static_cast<int>(i), toDescriptors, candidates, options.nndr, d);
      if (j < 0) continue;
      int& owner = claimedBy[static_cast<size_t>(j)];
      if (owner >= 0 && matches[static_cast<size_t>(owner)].distance <= d) continue;
      if (owner >= 0) matches[static_cast<size_t>(owner)].queryIdx = -1;  // displaced
      owner = static_cast<int>(matches.size());
      matches.emplace_back(static_cast<int>(i), j, d);
    }
    matches.erase(std::remove_if(matches.begin(), matches.end(), [](const cv::DMatch& m) { return m.queryIdx < 0; }),
                  matches.end());
    return matches;
  }
  const PointGrid grid(projected, radius);
  for (size_t j = 0; j < toPoints.size(); ++j) {
    grid.query(toPoints[j], radius, candidates);
    float d = 0.0f;
    const int i = bestCandidate(toDescriptors, static_cast<int>(j), fromDescriptors, candidates, options.nndr, d);
    if (i >= 0) matches.emplace_back(i, static_cast<int>(j), d);
  }
  return uniqueOnQuery(matches);
}

std::vector<cv::DMatch> matchByWordIds(const std::vector<int>& fromIds, const std::vector<int>& toIds,
                                       const std::vector<cv::Point2f>& projected,
                                       const std::vector<cv::KeyPoint>& toKeypoints, float radius) {
  if (!projected.empty() && (projected.size() != fromIds.size() || toKeypoints.size() != toIds.size())) {
    throw std::invalid_argument("matchByWordIds: one projection per reference id and one keypoint per new id expected");
  }
  // Index of the feature with each id, -1 once the id is seen a second time.
  auto uniqueIndex = [](const std::vector<int>& ids) {
    std::unordered_map<int, int> index;
    for (size_t i = 0; i < ids.size(); ++i) {
      auto [it, inserted] = index.emplace(ids[i], static_cast<int>(i));
      if (!inserted) it->second = -1;
    }
    return index;
  };
  const std::unordered_map<int, int> to = uniqueIndex(toIds);
  const std::unordered_map<int, int> from = uniqueIndex(fromIds);
  std::vector<cv::DMatch> matches;
  const float radius2 = radius * radius;
  for (size_t i = 0; i < fromIds.size(); ++i) {
    const auto f = from.find(fromIds[i]);
    if (f->second < 0) continue;
    const auto t = to.find(fromIds[i]);
    if (t == to.end() || t->second < 0) continue;
    if (!projected.empty()) {
      const cv::Point2f& p = projected[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
      const cv::Point2f d = p - toKeypoints[static_cast<size_t>(t->second)].pt;
      if (d.dot(d) > radius2) continue;
    }
    matches.emplace_back(static_cast<int>(i), t->second, 0.0f);
  }
  return matches;
}

std::vector<cv::Point2f> trackOpticalFlow(const cv::Mat& fromGrey, const cv::Mat& toGrey,
                                          const std::vector<cv::Point2f>& fromPoints,
                                          const std::vector<cv::Point2f>& initial,
                                          const CorrespondenceOptions& options, std::vector<unsigned char>& status) {
  status.assign(fromPoints.size(), 0);
  if (fromPoints.empty()) return {};
  if (fromGrey.type() != CV_8UC1 || toGrey.type() != CV_8UC1 || fromGrey.size() != toGrey.size()) {
    throw std::invalid_argument("trackOpticalFlow: two 8-bit grey images of the same size expected");
  }
  std::vector<cv::Point2f> toPoints;
  int flags = 0;
  if (initial.size() == fromPoints.size()) {
    toPoints = initial;
    // A point whose guess is unusable starts from its own position.
    for (size_t i = 0; i < toPoints.size(); ++i) {
      if (!std::isfinite(toPoints[i].x) || !std::isfinite(toPoints[i].y)) toPoints[i] = fromPoints[i];
    }
    flags = cv::OPTFLOW_USE_INITIAL_FLOW;
  }
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(
      fromGrey, toGrey, fromPoints, toPoints, status, error, cv::Size(options.flowWinSize, options.flowWinSize),
      options.flowMaxLevel,
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, options.flowIterations, options.flowEps), flags);
  for (size_t i = 0; i < toPoints.size(); ++i) {
    const cv::Point2f& p = toPoints[i];
    if (status[i] && (p.x < 0.0f || p.y < 0.0f || p.x > toGrey.cols - 1 || p.y > toGrey.rows - 1)) status[i] = 0;
  }
  if (options.flowBackCheck > 0.0f) {
    // Forward-backward consistency (Kalal et al., ICPR 2010): a point tracked onto the wrong
    // texture rarely tracks back to where it started. Large motions between a key frame and
    // the current frame make such drifting tracks common, and RANSAC alone lets a cluster of
    // them through. A point that cannot be tracked back at all is kept: the backward pass
    // measures its gradients in the new image, which motion blur or interpolation may have
    // weakened under LK's eigenvalue threshold although the forward track is right.
    std::vector<cv::Point2f> back = fromPoints;
    std::vector<unsigned char> backStatus;
    cv::calcOpticalFlowPyrLK(
        toGrey, fromGrey, toPoints, back, backStatus, error, cv::Size(options.flowWinSize, options.flowWinSize),
        options.flowMaxLevel,
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, options.flowIterations, options.flowEps),
        cv::OPTFLOW_USE_INITIAL_FLOW);
    const float max2 = options.flowBackCheck * options.flowBackCheck;
    for (size_t i = 0; i < toPoints.size(); ++i) {
      const cv::Point2f d = back[i] - fromPoints[i];
      if (status[i] && backStatus[i] && d.dot(d) > max2) status[i] = 0;
    }
  }
  return toPoints;
}

}  // namespace rtabmap

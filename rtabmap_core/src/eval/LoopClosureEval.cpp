#include "rtabmap_core/eval/LoopClosureEval.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>

#include "ReaderSupport.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap {

using eval_detail::throwAt;

std::vector<LoopDetection> readLoopDetections(const std::string& path) {
  eval_detail::TextLineReader in(path);
  std::vector<LoopDetection> detections;
  std::set<int> seen;
  std::string line;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    const long n = in.lineNumber();
    const auto f = eval_detail::splitFields(line, true);
    if (f.size() != 3 && f.size() != 2) {
      throwAt(path, n, "expected `query_id matched_id confidence`, got " + std::to_string(f.size()) + " fields");
    }
    LoopDetection d;
    const long long q = eval_detail::parseInteger(f[0], path, n, "query id");
    const long long m = eval_detail::parseInteger(f[1], path, n, "matched id");
    if (q < 1 || q > std::numeric_limits<int>::max()) throwAt(path, n, "query id must be >= 1 (ids are 1-based)");
    if (m < 0 || m > std::numeric_limits<int>::max()) throwAt(path, n, "matched id must be >= 0 (0 = no loop)");
    d.queryId = static_cast<int>(q);
    d.matchedId = static_cast<int>(m);
    d.confidence = f.size() == 3 ? eval_detail::parseNumber(f[2], path, n, "confidence") : 1.0;
    if (!seen.insert(d.queryId).second) {
      throwAt(path, n, "query " + std::to_string(d.queryId) + " appears twice");
    }
    detections.push_back(d);
  }
  return detections;
}

// ---------------------------------------------------------------------------------------------
// LoopGroundTruth
// ---------------------------------------------------------------------------------------------

void LoopGroundTruth::addLoop(int a, int b) {
  loops_[static_cast<size_t>(a - 1)].push_back(b);
  loops_[static_cast<size_t>(b - 1)].push_back(a);
}

void LoopGroundTruth::finish() {
  for (auto* lists : {&loops_, &ambiguous_}) {
    for (auto& l : *lists) {
      std::sort(l.begin(), l.end());
      l.erase(std::unique(l.begin(), l.end()), l.end());
    }
  }
}

LoopGroundTruth LoopGroundTruth::fromMatrix(const cv::Mat& matrix) {
  if (matrix.empty()) throw FormatError("loop ground truth: empty matrix");
  if (matrix.rows != matrix.cols) {
    throw FormatError("loop ground truth: the matrix must be square (N x N images), got " +
                      std::to_string(matrix.rows) + " x " + std::to_string(matrix.cols));
  }
  cv::Mat m = matrix;
  if (m.channels() > 1) {
    std::vector<cv::Mat> planes;
    cv::split(m, planes);
    m = planes[0].clone();
    for (size_t i = 1; i < planes.size(); ++i) m = cv::max(m, planes[i]);
  }
  cv::Mat nonZero = m != 0;  // CV_8U, 255 where non-zero
  LoopGroundTruth gt;
  gt.size_ = m.rows;
  gt.loops_.assign(static_cast<size_t>(m.rows), {});
  for (int r = 0; r < nonZero.rows; ++r) {
    const unsigned char* row = nonZero.ptr<unsigned char>(r);
    for (int c = 0; c < nonZero.cols; ++c) {
      if (row[c] && r != c) gt.addLoop(r + 1, c + 1);
    }
  }
  gt.finish();
  return gt;
}

LoopGroundTruth LoopGroundTruth::readMatrix(const std::string& path) {
  const std::string ext = eval_detail::toLower(std::filesystem::path(path).extension().string());
  static const std::set<std::string> kImages = {".png", ".bmp", ".pgm", ".ppm", ".jpg", ".jpeg", ".tif", ".tiff"};
  if (kImages.count(ext)) {
    const cv::Mat image = eval_detail::readImage(path, cv::IMREAD_UNCHANGED);
    try {
      return fromMatrix(image);
    } catch (const FormatError& e) {
      throw FormatError(path + ": " + e.what());
    }
  }
  eval_detail::TextLineReader in(path);
  std::vector<std::vector<unsigned char>> rows;
  std::string line;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    const auto f = eval_detail::splitFields(line, true);
    if (!rows.empty() && f.size() != rows.front().size()) {
      throwAt(path, in.lineNumber(),
              "matrix row of " + std::to_string(f.size()) + " values, the first row has " +
                  std::to_string(rows.front().size()));
    }
    std::vector<unsigned char> row(f.size());
    for (size_t i = 0; i < f.size(); ++i) {
      row[i] = eval_detail::parseNumber(f[i], path, in.lineNumber(), "matrix value") != 0.0 ? 1 : 0;
    }
    rows.push_back(std::move(row));
  }
  if (rows.empty()) throw FormatError(path + ": empty ground-truth matrix");
  if (rows.size() != rows.front().size()) {
    throw FormatError(path + ": the ground-truth matrix must be square, got " + std::to_string(rows.size()) +
                      " rows of " + std::to_string(rows.front().size()) + " values");
  }
  cv::Mat m(static_cast<int>(rows.size()), static_cast<int>(rows.size()), CV_8UC1);
  for (int r = 0; r < m.rows; ++r) std::copy(rows[r].begin(), rows[r].end(), m.ptr<unsigned char>(r));
  return fromMatrix(m);
}

LoopGroundTruth LoopGroundTruth::fromPoses(const std::vector<Transform>& poses, double maxDistance,
                                           double maxAngle, int minFrameGap) {
  PoseCriteria criteria;
  criteria.maxDistance = maxDistance;
  criteria.maxAngle = maxAngle;
  criteria.minFrameGap = minFrameGap;
  return fromPoses(poses, criteria);
}

namespace {

// The angle that PoseCriteria compares between poses a and b (radians).
double poseAngle(const Transform& a, const Transform& b, const LoopGroundTruth::PoseCriteria& criteria) {
  if (!criteria.viewingDirectionOnly) return (a.inverse() * b).getAngle();
  const Eigen::Vector3d da = a.rotationMatrix() * criteria.viewingAxis;
  const Eigen::Vector3d db = b.rotationMatrix() * criteria.viewingAxis;
  return std::acos(std::clamp(da.dot(db) / (da.norm() * db.norm()), -1.0, 1.0));
}

}  // namespace

LoopGroundTruth LoopGroundTruth::fromPoses(const std::vector<Transform>& poses, const PoseCriteria& criteria) {
  const double maxDistance = criteria.maxDistance;
  const double ambiguousDistance = criteria.ambiguousDistance;
  if (!(maxDistance >= 0.0)) throw FormatError("loop ground truth: the distance threshold must be >= 0");
  if (!(ambiguousDistance >= 0.0)) throw FormatError("loop ground truth: the ambiguous distance must be >= 0");
  if (criteria.viewingDirectionOnly && !(criteria.viewingAxis.norm() > 0.0)) {
    throw FormatError("loop ground truth: the viewing axis must not be zero");
  }
  const bool band = ambiguousDistance > 0.0;
  if (band && ambiguousDistance < maxDistance) {
    throw FormatError("loop ground truth: the ambiguous band (" + std::to_string(ambiguousDistance) +
                      " m) must reach at least the loop distance (" + std::to_string(maxDistance) + " m)");
  }
  LoopGroundTruth gt;
  gt.size_ = static_cast<int>(poses.size());
  gt.loops_.assign(poses.size(), {});
  if (band) gt.ambiguous_.assign(poses.size(), {});
  const double maxSq = maxDistance * maxDistance;
  const double bandSq = ambiguousDistance * ambiguousDistance;
  const size_t gap = static_cast<size_t>(std::max(1, criteria.minFrameGap));
  for (size_t i = 0; i < poses.size(); ++i) {
    if (poses[i].isNull()) continue;
    const Eigen::Vector3d pi = poses[i].translation();
    for (size_t j = 0; j + gap <= i; ++j) {
      if (poses[j].isNull()) continue;
      const double sq = (poses[j].translation() - pi).squaredNorm();
      if (sq > std::max(maxSq, band ? bandSq : 0.0)) continue;
      const double angle = poseAngle(poses[i], poses[j], criteria);
      const int a = static_cast<int>(i) + 1, b = static_cast<int>(j) + 1;
      if (sq <= maxSq && (criteria.maxAngle <= 0.0 || angle <= criteria.maxAngle)) {
        gt.addLoop(a, b);
      } else if (band && (criteria.ambiguousAngle <= 0.0 || angle <= criteria.ambiguousAngle)) {
        gt.ambiguous_[i].push_back(b);
        gt.ambiguous_[j].push_back(a);
      }
    }
  }
  gt.finish();
  return gt;
}

bool LoopGroundTruth::isLoop(int a, int b) const {
  if (a < 1 || b < 1 || a > size_ || b > size_ || a == b) return false;
  const auto& l = loops_[static_cast<size_t>(a - 1)];
  return std::binary_search(l.begin(), l.end(), b);
}

bool LoopGroundTruth::isAmbiguous(int a, int b) const {
  if (ambiguous_.empty() || a < 1 || b < 1 || a > size_ || b > size_ || a == b) return false;
  const auto& l = ambiguous_[static_cast<size_t>(a - 1)];
  return std::binary_search(l.begin(), l.end(), b);
}

bool LoopGroundTruth::hasLoopWithEarlier(int id) const {
  if (id < 1 || id > size_) return false;
  const auto& l = loops_[static_cast<size_t>(id - 1)];
  return !l.empty() && l.front() < id;
}

size_t LoopGroundTruth::positives() const {
  size_t n = 0;
  for (int id = 1; id <= size_; ++id) n += hasLoopWithEarlier(id) ? 1 : 0;
  return n;
}

// ---------------------------------------------------------------------------------------------
// Precision / recall
// ---------------------------------------------------------------------------------------------

LoopClosurePR computeLoopClosurePR(const std::vector<LoopDetection>& detections,
                                   const LoopGroundTruth& groundTruth, double threshold) {
  LoopClosurePR r;
  r.queries = detections.size();
  r.positives = groundTruth.positives();
  r.threshold = threshold;
  struct Scored {
    double confidence;
    bool correct;
    bool countsForRecall;  // a correct match of a positive query
  };
  std::vector<Scored> scored;
  for (const auto& d : detections) {
    if (d.matchedId == 0) continue;
    if (d.queryId > groundTruth.size() || d.matchedId > groundTruth.size()) {
      ++r.ignored;
      continue;
    }
    ++r.detections;
    const bool correct = groundTruth.isLoop(d.queryId, d.matchedId);
    if (!correct && groundTruth.isAmbiguous(d.queryId, d.matchedId)) {
      if (d.confidence >= threshold) ++r.ambiguous;
      continue;  // neither true nor false, at any threshold of the sweep
    }
    scored.push_back({d.confidence, correct, correct && groundTruth.hasLoopWithEarlier(d.queryId)});
  }
  auto ratio = [](size_t a, size_t b, double ifZero) {
    return b == 0 ? ifZero : static_cast<double>(a) / static_cast<double>(b);
  };
  size_t recalled = 0;
  for (const auto& s : scored) {
    if (s.confidence < threshold) continue;
    if (s.correct) {
      ++r.truePositives;
      if (s.countsForRecall) ++recalled;
    } else {
      ++r.falsePositives;
    }
  }
  r.falseNegatives = r.positives - recalled;
  r.precision = ratio(r.truePositives, r.truePositives + r.falsePositives, 1.0);
  r.recall = ratio(recalled, r.positives, 0.0);

  std::stable_sort(scored.begin(), scored.end(),
                   [](const Scored& a, const Scored& b) { return a.confidence > b.confidence; });
  size_t tp = 0, fp = 0, rec = 0;
  r.thresholdAt100Precision = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < scored.size();) {
    const double c = scored[i].confidence;
    for (; i < scored.size() && scored[i].confidence == c; ++i) {
      if (scored[i].correct) {
        ++tp;
        if (scored[i].countsForRecall) ++rec;
      } else {
        ++fp;
      }
    }
    PrecisionRecallPoint p;
    p.threshold = c;
    p.truePositives = tp;
    p.falsePositives = fp;
    p.precision = ratio(tp, tp + fp, 1.0);
    p.recall = ratio(rec, r.positives, 0.0);
    r.curve.push_back(p);
    if (fp == 0 && tp > 0 && p.recall >= r.recallAt100Precision) {
      r.recallAt100Precision = p.recall;
      r.thresholdAt100Precision = c;
    }
  }
  return r;
}

}  // namespace rtabmap

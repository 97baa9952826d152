#include "rtabmap_core/eval/RelationError.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "ReaderSupport.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap {

std::vector<Relation> readRelations(const std::string& path) {
  eval_detail::TextLineReader in(path);
  std::vector<Relation> relations;
  std::string line;
  while (in.next(line)) {
    if (eval_detail::isCommentOrBlank(line)) continue;
    const long n = in.lineNumber();
    const auto f = eval_detail::splitFields(line);
    if (f.size() != 8) {
      eval_detail::throwAt(path, n,
                           "expected 8 values `t1 t2 x y z roll pitch yaw`, got " + std::to_string(f.size()));
    }
    double v[8];
    for (int i = 0; i < 8; ++i) {
      v[i] = eval_detail::parseNumber(f[i], path, n, i < 2 ? "timestamp" : "relative pose value");
    }
    Relation r;
    r.stamp1 = v[0];
    r.stamp2 = v[1];
    r.pose = Transform(v[2], v[3], v[4], v[5], v[6], v[7]);
    r.line = static_cast<int>(n);
    relations.push_back(r);
  }
  if (relations.empty()) throw FormatError(path + ": no relation in the file");
  return relations;
}

RelationResult computeRelationError(const Trajectory& estimate, const std::vector<Relation>& relations,
                                    const RelationOptions& options) {
  Trajectory sorted = estimate;
  if (!sorted.isSorted()) sorted.sortByStamp();
  RelationResult r;
  r.relations = relations.size();
  std::vector<double> localT, localR, loopT, loopR;
  for (size_t k = 0; k < relations.size(); ++k) {
    const Relation& rel = relations[k];
    const long i = sorted.nearest(rel.stamp1, options.maxTimeDifference);
    const long j = sorted.nearest(rel.stamp2, options.maxTimeDifference);
    if (i < 0 || j < 0 || sorted.poses[static_cast<size_t>(i)].pose.isNull() ||
        sorted.poses[static_cast<size_t>(j)].pose.isNull()) {
      r.skippedRelations.push_back(k);
      continue;
    }
    const Transform delta = sorted.poses[static_cast<size_t>(i)].pose.inverse() *
                            sorted.poses[static_cast<size_t>(j)].pose;
    const Transform error = rel.pose.inverse() * delta;
    r.translationErrors.push_back(error.getNorm());
    r.rotationErrors.push_back(error.getAngle() * 180.0 / M_PI);
    if (options.localSpan > 0.0) {
      const bool local = std::fabs(rel.stamp2 - rel.stamp1) <= options.localSpan;
      (local ? localT : loopT).push_back(r.translationErrors.back());
      (local ? localR : loopR).push_back(r.rotationErrors.back());
    }
  }
  r.used = r.translationErrors.size();
  r.skipped = r.skippedRelations.size();
  if (r.used == 0) {
    std::ostringstream s;
    s.precision(17);
    s << "relations: none of the " << relations.size()
      << " relations has estimated poses at both its stamps (within " << options.maxTimeDifference
      << " s)";
    if (!relations.empty() && !sorted.empty()) {
      double lo = relations.front().stamp1, hi = lo;
      for (const auto& rel : relations) {
        lo = std::min({lo, rel.stamp1, rel.stamp2});
        hi = std::max({hi, rel.stamp1, rel.stamp2});
      }
      s << "; relation stamps " << lo << " .. " << hi << ", estimate stamps "
        << sorted.poses.front().stamp << " .. " << sorted.poses.back().stamp;
    }
    throw FormatError(s.str());
  }
  r.translation = computeErrorStats(r.translationErrors);
  r.rotation = computeErrorStats(r.rotationErrors);
  r.translationSquaredMean = r.translation.rmse * r.translation.rmse;
  r.rotationSquaredMean = r.rotation.rmse * r.rotation.rmse;
  r.localTranslation = computeErrorStats(localT);  // count 0 when a side is empty
  r.localRotation = computeErrorStats(localR);
  r.loopTranslation = computeErrorStats(loopT);
  r.loopRotation = computeErrorStats(loopR);
  return r;
}

}  // namespace rtabmap

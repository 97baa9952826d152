#include "rtabmap_core/eval/RelationError.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <utility>

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
    r.usedRelations.push_back(k);
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

std::vector<size_t> worstRelations(const RelationResult& result, size_t n) {
  std::vector<size_t> order(result.translationErrors.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  const auto larger = [&](size_t a, size_t b) { return result.translationErrors[a] > result.translationErrors[b]; };
  std::stable_sort(order.begin(), order.end(), larger);
  if (order.size() > n) order.resize(n);
  return order;
}

RelationConsistency relationConsistency(const std::vector<Relation>& relations, double maxTimeDifference) {
  // Instants: the relations' stamps, those within maxTimeDifference of the previous one merged.
  std::vector<double> stamps;
  for (const Relation& r : relations) {
    stamps.push_back(r.stamp1);
    stamps.push_back(r.stamp2);
  }
  std::sort(stamps.begin(), stamps.end());
  std::vector<double> firstOfInstant;
  for (double t : stamps) {
    if (firstOfInstant.empty() || t - firstOfInstant.back() > maxTimeDifference) {
      firstOfInstant.push_back(t);
    }
  }
  auto instantOf = [&](double t) {
    const auto it = std::upper_bound(firstOfInstant.begin(), firstOfInstant.end(), t);
    return static_cast<int>(it - firstOfInstant.begin()) - 1;
  };
  // Sides from the earlier instant to the later one (a relation given backwards is inverted); the
  // first relation of a pair of instants is the side.
  std::map<std::pair<int, int>, Transform> sides;
  std::map<int, std::vector<int>> later;  // instant -> the later instants it has a side to
  for (const Relation& r : relations) {
    const int a = instantOf(r.stamp1), b = instantOf(r.stamp2);
    if (a == b) continue;
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    if (sides.count(key)) continue;
    sides.emplace(key, a < b ? r.pose : r.pose.inverse());
    later[key.first].push_back(key.second);
  }
  std::vector<double> translation, rotation;
  for (const auto& [a, bs] : later) {
    for (int b : bs) {
      const auto bc = later.find(b);
      if (bc == later.end()) continue;
      for (int c : bc->second) {
        const auto ac = sides.find({a, c});
        if (ac == sides.end()) continue;
        const Transform e = ac->second.inverse() * sides.at({a, b}) * sides.at({b, c});
        translation.push_back(e.getNorm());
        rotation.push_back(e.getAngle() * 180.0 / M_PI);
      }
    }
  }
  RelationConsistency out;
  out.triangles = translation.size();
  out.translation = computeErrorStats(translation);
  out.rotation = computeErrorStats(rotation);
  out.relationRms = out.translation.rmse / std::sqrt(3.0);
  return out;
}

}  // namespace rtabmap

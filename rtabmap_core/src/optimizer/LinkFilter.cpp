// graph:: link filtering and look-up.
#include <cmath>

#include "rtabmap_core/optimizer/Graph.h"

namespace rtabmap::graph {

Links filterLinks(const Links& links, const std::set<Link::Type>& types, bool keep) {
  Links out;
  for (const auto& entry : links) {
    if ((types.count(entry.second.type()) != 0) == keep) out.insert(out.end(), entry);
  }
  return out;
}

Links filterLinks(const Links& links, Link::Type type, bool keep) {
  return filterLinks(links, std::set<Link::Type>{type}, keep);
}

bool isLoopClosureOrProximity(Link::Type type) {
  return type == Link::kGlobalClosure || type == Link::kLocalSpaceClosure ||
         type == Link::kLocalTimeClosure || type == Link::kUserClosure;
}

namespace {

bool sameTransform(const Transform& a, const Transform& b, double tolerance) {
  if (a.isNull() || b.isNull()) return a.isNull() && b.isNull();
  return (a.toMatrix4d() - b.toMatrix4d()).cwiseAbs().maxCoeff() <= tolerance;
}

}  // namespace

Links filterDuplicateLinks(const Links& links) {
  Links out;
  for (const auto& entry : links) {
    const Link& link = entry.second;
    bool duplicate = false;
    if (link.from() != link.to()) {
      // A kept link to -> from (keyed by `to`) that is this one reversed.
      const auto range = out.equal_range(link.to());
      for (auto it = range.first; it != range.second && !duplicate; ++it) {
        const Link& kept = it->second;
        duplicate = kept.to() == link.from() && kept.type() == link.type() &&
                    !link.transform().isNull() &&
                    sameTransform(kept.transform(), link.transform().inverse(), 1e-6);
      }
    }
    if (!duplicate) out.insert(out.end(), entry);
  }
  return out;
}

Links::const_iterator findLink(const Links& links, int a, int b, bool bothWays, Link::Type type) {
  auto matches = [&](const Link& link, int from, int to) {
    return link.from() == from && link.to() == to && (type == Link::kUndef || link.type() == type);
  };
  auto range = links.equal_range(a);
  for (auto it = range.first; it != range.second; ++it) {
    if (matches(it->second, a, b)) return it;
  }
  if (bothWays) {
    range = links.equal_range(b);
    for (auto it = range.first; it != range.second; ++it) {
      if (matches(it->second, b, a)) return it;
    }
  }
  return links.end();
}

}  // namespace rtabmap::graph

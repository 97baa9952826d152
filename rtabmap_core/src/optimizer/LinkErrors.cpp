#include "rtabmap_core/optimizer/LinkErrors.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "PoseMath.h"
#include "rtabmap_core/optimizer/Graph.h"

namespace rtabmap::graph {

double LinkError::worstRatio() const { return std::max(translationalRatio(), angularRatio()); }

namespace {

// Largest variance (1 / information) among the given diagonal entries.
double largestVariance(const Link::InfMatrix& info, std::initializer_list<int> axes) {
  double smallestInfo = std::numeric_limits<double>::infinity();
  for (int axis : axes) smallestInfo = std::min(smallestInfo, info(axis, axis));
  return 1.0 / smallestInfo;
}

}  // namespace

std::vector<LinkError> computeLinkErrors(const std::map<int, Transform>& poses,
                                         const std::multimap<int, Link>& links, bool is2D,
                                         bool onlyLoopClosures) {
  std::vector<LinkError> errors;
  for (const auto& [key, link] : links) {
    (void)key;
    if (link.from() == link.to() || link.transform().isNull()) continue;
    if (link.type() == Link::kPosePrior || link.type() == Link::kGravity) continue;
    if (onlyLoopClosures && !isLoopClosureOrProximity(link.type())) continue;
    const auto a = poses.find(link.from());
    const auto b = poses.find(link.to());
    if (a == poses.end() || b == poses.end() || a->second.isNull() || b->second.isNull()) continue;

    const Transform e = link.transform().inverse() * (a->second.inverse() * b->second);
    LinkError error;
    error.from = link.from();
    error.to = link.to();
    error.type = link.type();
    const Link::InfMatrix& info = link.infMatrix();
    if (is2D) {
      error.translationalError = std::hypot(e.x(), e.y());
      error.angularError = std::fabs(optimizer_internal::wrapAngle(e.yaw()));
      error.translationalStd = std::sqrt(largestVariance(info, {0, 1}));
      error.angularStd = std::sqrt(largestVariance(info, {5}));
    } else {
      error.translationalError = e.getNorm();
      error.angularError = e.getAngle();
      error.translationalStd = std::sqrt(largestVariance(info, {0, 1, 2}));
      error.angularStd = std::sqrt(largestVariance(info, {3, 4, 5}));
    }
    errors.push_back(error);
  }
  std::stable_sort(errors.begin(), errors.end(), [](const LinkError& x, const LinkError& y) {
    return x.worstRatio() > y.worstRatio();
  });
  return errors;
}

MaxErrorCheck checkMaxLinkError(const std::map<int, Transform>& optimizedPoses,
                                const std::multimap<int, Link>& links, double maxErrorRatio,
                                bool is2D) {
  MaxErrorCheck check;
  check.threshold = maxErrorRatio;
  const std::vector<LinkError> errors = computeLinkErrors(optimizedPoses, links, is2D, true);
  check.linksChecked = static_cast<int>(errors.size());
  for (const LinkError& error : errors) {
    if (check.worstTranslational.type == Link::kUndef ||
        error.translationalRatio() > check.worstTranslational.translationalRatio()) {
      check.worstTranslational = error;
    }
    if (check.worstAngular.type == Link::kUndef ||
        error.angularRatio() > check.worstAngular.angularRatio()) {
      check.worstAngular = error;
    }
    if (maxErrorRatio > 0.0 && error.worstRatio() > maxErrorRatio) check.offending.push_back(error);
  }
  check.rejected = !check.offending.empty();
  if (check.rejected) {
    const LinkError& worst = check.offending.front();
    const bool translational = worst.translationalRatio() >= worst.angularRatio();
    std::ostringstream s;
    s << std::setprecision(3) << "loop closure " << worst.from << "->" << worst.to << " ("
      << Link::typeName(worst.type) << "): ";
    if (translational) {
      s << "translational error " << worst.translationalError << " m is "
        << worst.translationalRatio() << " times its standard deviation " << worst.translationalStd
        << " m";
    } else {
      s << "angular error " << worst.angularError << " rad is " << worst.angularRatio()
        << " times its standard deviation " << worst.angularStd << " rad";
    }
    s << " (max " << maxErrorRatio << ")";
    if (check.offending.size() > 1) s << ", and " << check.offending.size() - 1 << " more";
    check.why = s.str();
  }
  return check;
}

}  // namespace rtabmap::graph

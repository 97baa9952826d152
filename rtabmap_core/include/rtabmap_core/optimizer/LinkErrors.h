#pragma once
// Rejecting wrong loop closures after optimisation (RGBD/OptimizeMaxError, JFR 2019 section
// 3.5): a wrong loop closure bends the optimised graph until the links around it, or itself,
// disagree with their measurement by far more than their uncertainty. For each loop-closure
// and proximity link, the error of the optimised relative pose against the link's transform is
// compared with the link's standard deviation; if the worst ratio exceeds the threshold, the
// SLAM pipeline removes the links added in that update and keeps the previous graph.
#include <map>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap::graph {

struct LinkError {
  int from = 0;
  int to = 0;
  Link::Type type = Link::kUndef;
  // Of E = Z^-1 * (Xi^-1 * Xj): translation norm (x, y only in 3DoF), metres; rotation angle
  // (|yaw| in 3DoF), radians.
  double translationalError = 0.0;
  double angularError = 0.0;
  // Standard deviations from the link's information diagonal: the largest variance of the
  // axes used (x, y[, z]; yaw[, roll, pitch]), i.e. the most lenient, as a conservative check
  // wants.
  double translationalStd = 0.0;
  double angularStd = 0.0;
  double translationalRatio() const { return translationalError / translationalStd; }
  double angularRatio() const { return angularError / angularStd; }
  double worstRatio() const;
};

// The error of every link whose both ends are in `poses` and whose type passes the filter:
// loop closures and proximity links (graph::isLoopClosureOrProximity) when onlyLoopClosures,
// every relative link otherwise. Sorted by decreasing worst ratio.
std::vector<LinkError> computeLinkErrors(const std::map<int, Transform>& poses,
                                         const std::multimap<int, Link>& links, bool is2D,
                                         bool onlyLoopClosures = true);

struct MaxErrorCheck {
  bool rejected = false;      // some link exceeds the threshold
  double threshold = 0.0;     // RGBD/OptimizeMaxError (0 = disabled: never rejected)
  int linksChecked = 0;
  // The worst link by translational ratio and by angular ratio (type kUndef when none checked).
  LinkError worstTranslational;
  LinkError worstAngular;
  // The links over the threshold, worst first.
  std::vector<LinkError> offending;
  // "loop closure 12->3 (GlobalClosure): translational error 5.01 m is 50.1 times its
  // standard deviation 0.1 m (max 3)", or "" when not rejected.
  std::string why;
};

// RGBD/OptimizeMaxError: checks the loop closures and proximity links of optimised poses.
MaxErrorCheck checkMaxLinkError(const std::map<int, Transform>& optimizedPoses,
                                const std::multimap<int, Link>& links, double maxErrorRatio,
                                bool is2D);

}  // namespace rtabmap::graph

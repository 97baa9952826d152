#include "rtabmap_core/memory/LandmarkLinks.h"

#include <Eigen/LU>

#include <string>

namespace rtabmap::memory {

std::vector<Link> landmarkLinksOf(int id, const Landmarks& landmarks, std::vector<std::string>* why) {
  std::vector<Link> links;
  auto refuse = [&](const Landmark& l, const std::string& reason) {
    if (why) why->push_back("landmark " + std::to_string(l.id) + " of node " + std::to_string(id) + ": " + reason);
  };
  for (const auto& [key, l] : landmarks) {
    (void)key;
    if (l.id <= 0) {
      refuse(l, "ids start at 1 (its graph node is -id)");
      continue;
    }
    if (l.pose.isNull() || !l.pose.toEigen().matrix().allFinite()) {
      refuse(l, "no valid pose");
      continue;
    }
    const Eigen::Matrix<double, 6, 6>& c = l.covariance;
    if (!c.allFinite() || c.diagonal().minCoeff() <= 0.0) {
      refuse(l, "its covariance is not finite and positive on the diagonal");
      continue;
    }
    Link::InfMatrix information = c.inverse();
    if (!information.allFinite()) {
      // A singular full covariance: keep its diagonal, what every detector at least gives.
      information = c.diagonal().cwiseInverse().asDiagonal();
    }
    links.emplace_back(id, -l.id, Link::kLandmark, l.pose, 0.5 * (information + information.transpose()));
  }
  return links;
}

}  // namespace rtabmap::memory

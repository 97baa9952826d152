#pragma once
// Proximity detection by time (RGBD/ProximityByTime, the original's "local loop closure in
// time"): the new node registered against each node of Short-Term Memory it is not linked to
// yet. Loop-closure detection never looks at Short-Term Memory (its nodes look like the new one
// because they are the robot's last seconds), and proximity by space skips it too; a robot that
// turns on the spot or backs up sees again what it saw a few nodes ago, and these links tie
// those nodes together directly instead of through a chain of odometry links. The guess is the
// graph's relative pose; the links are checked by the optimisation with the others
// (RGBD/OptimizeMaxError).
#include <map>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap {

namespace memory {
class Memory;
}
class LinkRegistration;

struct ProximityByTimeResult {
  std::vector<Link> links;              // from the new node to the Short-Term Memory node
  int checked = 0;                      // registrations tried
  std::vector<std::string> rejections;  // why each failed
};

// Candidates: the Short-Term Memory nodes of the new node's map that have a pose in `poses` and
// no link to it. Links carry the registration's covariance as information.
ProximityByTimeResult detectProximityByTime(memory::Memory& memory, int newId, const std::map<int, Transform>& poses,
                                            const LinkRegistration& registration, bool covOffDiagIgnored);

}  // namespace rtabmap

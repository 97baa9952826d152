#include "ProximityByTime.h"

#include "LinkRegistration.h"
#include "rtabmap_core/memory/Memory.h"
#include "rtabmap_core/registration/RegistrationInfo.h"

namespace rtabmap {

ProximityByTimeResult detectProximityByTime(memory::Memory& memory, int newId, const std::map<int, Transform>& poses,
                                            const LinkRegistration& registration, bool covOffDiagIgnored) {
  ProximityByTimeResult result;
  Signature* current = memory.mutableSignature(newId);
  if (!current || !poses.count(newId)) return result;
  // Newest first: the nodes nearest in time overlap the most.
  for (auto it = memory.stm().rbegin(); it != memory.stm().rend(); ++it) {
    const int id = *it;
    Signature* other = id == newId ? nullptr : memory.mutableSignature(id);
    if (!other || other->isIntermediate() || other->mapId() != current->mapId() || current->hasLink(id) ||
        !poses.count(id)) {
      continue;
    }
    ++result.checked;
    RegistrationInfo info;
    const Transform guess = poses.at(newId).inverse() * poses.at(id);  // new -> STM node
    const Transform t = registration.compute(*current, *other, guess, &info);
    if (t.isNull()) {
      result.rejections.push_back("proximity by time " + std::to_string(newId) + "->" + std::to_string(id) + ": " +
                                  info.rejectedMsg);
      continue;
    }
    result.links.emplace_back(newId, id, Link::kLocalTimeClosure, t, informationOf(info.covariance, covOffDiagIgnored));
  }
  return result;
}

}  // namespace rtabmap

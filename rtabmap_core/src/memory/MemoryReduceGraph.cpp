// Graph reduction (Mem/ReduceGraph): a location that closed a loop with an older one is the same
// place seen again; when it leaves STM it is merged into the older location instead of joining
// WM, so a robot that keeps revisiting the same places keeps the graph (and the LTM) the size
// of the places, not of the time spent in them.
//
// The graph stays connected and keeps its constraints: the locations the reduced one was linked
// to (its neighbours in the chain, the ones it closed loops with) are linked to each other
// through its links, composed (noise of both; type NeighborMerged, as the original names them;
// see reduce()). The reduced location is never written to the LTM (it was still in STM), and
// the links of its saved neighbours to it leave the LTM too.
#include <algorithm>
#include <set>
#include <vector>

#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/Memory.h"

namespace rtabmap::memory {

namespace {

// The measured links a reduced location hands on: loop closures and proximity links.
bool handedOn(Link::Type type) {
  return type == Link::kGlobalClosure || type == Link::kLocalSpaceClosure || type == Link::kLocalTimeClosure ||
         type == Link::kUserClosure;
}

}  // namespace

// The oldest location in RAM that `s` closed a loop with (appearance, proximity in space or
// the user's link), 0 if none. Kept whatever their links: intermediate nodes (a pose of the
// trajectory, no place), labelled locations (a goal by name), locations with a pose prior or a
// landmark (an absolute measurement belongs to the pose it was taken from), locations already
// in the LTM, and links carrying a user's data (the original's rule; the record of the scans a
// proximity link was matched against, RGBD/ScanMatchingIdsSavedInLinks, is no user's data).
// Proximity in time links consecutive views of one traversal, not a revisit: they do not
// reduce. Nor does a location next to intermediate nodes (Rtabmap/CreateIntermediateNodes):
// they are there to keep the whole trajectory, and they leave WM with the location after them,
// which must stay.
int Memory::reductionTarget(const Signature& s) const {
  if (!options_.incremental || s.isIntermediate() || !s.label().empty() || s.isSaved()) return 0;
  int into = 0;
  for (const auto& [to, link] : s.getLinks()) {
    if (link.type() == Link::kPosePrior || link.type() == Link::kLandmark) return 0;
    if (link.type() == Link::kNeighbor && to != s.id() && isIntermediate(to)) return 0;
    if (into != 0 || to >= s.id() || (!link.userData().empty() && !link.hasScanIdsUserData())) continue;
    const Link::Type t = link.type();
    if (t != Link::kGlobalClosure && t != Link::kLocalSpaceClosure && t != Link::kUserClosure) continue;
    auto older = signatures_.find(to);
    if (older != signatures_.end() && !older->second.isIntermediate()) into = to;
  }
  return into;
}

void Memory::reduce(int id, int into, std::set<int>& relinked) {
  Signature& s = at(id);
  const std::multimap<int, Link> links = s.getLinks();
  const bool writeLtm = ltm_ != nullptr && options_.incremental;
  // The other end of each link may be in RAM or, transferred meanwhile, only in the LTM
  // (mutableSignature() is null then).

  // The links the reduced location hands on (to its neighbours in the chain and the locations it
  // closed loops with), from `id`. Marginalising it exactly would join all their ends in one
  // dense constraint; the graph takes pairwise links, so they are chained through one of them,
  // the hub: the best-measured link (least variance on its worst axis: usually odometry, since
  // proximity links along a corridor know little along it). Each other end gets hub^-1 then its
  // own link. The hub's measurement enters each of those k - 1 links, so its information is
  // split between them: in all, the graph counts it once.
  std::vector<Link> handed;
  for (const auto& [to, link] : links) {
    const Link::Type t = link.type();
    if (to != id && to > 0 && (t == Link::kNeighbor || t == Link::kNeighborMerged || handedOn(t))) handed.push_back(link);
  }
  if (handed.size() >= 2) {
    const auto hubIt = std::min_element(handed.begin(), handed.end(), [](const Link& a, const Link& b) {
      return a.transVariance(false) < b.transVariance(false);
    });
    Link fromHub = hubIt->inverse();  // hub -> id
    fromHub.setInfMatrix(fromHub.infMatrix() / static_cast<double>(handed.size() - 1));
    const int hub = fromHub.from();
    for (const Link& other : handed) {
      if (other.to() == hub) continue;
      Signature* a = mutableSignature(hub);
      Signature* b = mutableSignature(other.to());
      if ((a && a->hasLink(other.to())) || (b && b->hasLink(hub))) continue;  // already constrained
      const Link merged = fromHub.compose(other, Link::kNeighborMerged);
      if (a && b) {
        addLinkBetween(*a, *b, merged);
      } else if (a) {
        a->addLink(merged);
      } else if (b) {
        b->addLink(merged.inverse());
      }
      if (writeLtm && (!a || !b || a->isSaved() || b->isSaved())) ltm_->saveLink(merged);
    }
  }
  for (const auto& [to, link] : links) {
    if (to == id || to <= 0) continue;
    relinked.insert(to);
    Signature* other = mutableSignature(to);
    if (other) other->removeLink(id);
    if (writeLtm && (!other || other->isSaved())) ltm_->removeLink(to, id);
  }

  // The place lives on in the older location: it takes the weight the loop closure gave the
  // newer one (Memory::addLoopClosure left it 0), or it would be the first to leave WM.
  Signature& kept = at(into);
  kept.setWeight(kept.weight() + s.weight());
  removeFromVocabulary(id, s.getWords());
  stm_.erase(id);
  eraseFromRam(id);
  if (previousOfLast_ == id) previousOfLast_ = into;
  if (previousId_ == id) previousId_ = into;
  ++reducedTotal_;
}

}  // namespace rtabmap::memory

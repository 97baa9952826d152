// Transfer to and retrieval from the Long-Term Memory (T-RO 2013, Algorithms 3 and 4).
#include <opencv2/core.hpp>

#include <algorithm>
#include <map>
#include <stdexcept>

#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/Memory.h"

namespace rtabmap::memory {

// The recent part of WM: the locations added since the last loop closure, the newest first,
// at most Mem/RecentWmRatio of WM. While the robot explores new ground they are what a loop
// closure would connect to next, so they stay.
std::set<int> Memory::recentWm() const {
  std::set<int> recent;
  const size_t maxRecent = static_cast<size_t>(options_.recentWmRatio * static_cast<float>(wmLocations()));
  for (auto it = wm_.rbegin(); it != wm_.rend() && recent.size() < maxRecent; ++it) {
    if (it->first <= lastGlobalLoopClosureId_) break;
    if (!signatures_.at(it->first).isIntermediate()) recent.insert(it->first);
  }
  return recent;
}

std::vector<int> Memory::transferCandidates(const std::set<int>& immune) const {
  const std::set<int> recent = recentWm();
  std::vector<int> candidates;
  for (const auto& [id, age] : wm_) {
    (void)age;
    if (!immune.count(id) && !recent.count(id) && !signatures_.at(id).isIntermediate()) candidates.push_back(id);
  }
  // Lowest weight first; among equal weights the oldest: by time in WM (a retrieved location
  // is young again) or by id (Mem/TransferSortingByWeightId).
  std::stable_sort(candidates.begin(), candidates.end(), [this](int a, int b) {
    const int wa = signatures_.at(a).weight(), wb = signatures_.at(b).weight();
    if (wa != wb) return wa < wb;
    if (options_.transferSortingByWeightId) return a < b;
    const long ta = wm_.at(a), tb = wm_.at(b);
    return ta != tb ? ta < tb : a < b;
  });
  return candidates;
}

TransferResult Memory::transfer(const std::set<int>& immune, int minWordsRemoved, int maxWmSize, bool atLeastOne) {
  if (!ltm_) throw std::logic_error("Memory::transfer: no long-term memory (database) is attached");
  TransferResult result;
  // One location, then the intermediate nodes before it. False when the LTM refused it (disk
  // full...): it stays in WM rather than being lost, and so do the others (WM grows beyond its
  // budget; the map is complete).
  const auto moveToLtm = [&](int id) {
    Signature& s = at(id);
    if (!s.isSaved() || s.isModified() || s.isLinksModified()) saveToLtm(s);
    if (!s.isSaved() || s.isModified() || s.isLinksModified()) return false;
    result.wordsRemoved += removeFromVocabulary(id, s.getWords());
    wm_.erase(id);
    eraseFromRam(id);
    result.transferred.push_back(id);
    return true;
  };
  int transferredLocations = 0;
  for (int id : transferCandidates(immune)) {
    const bool wordsOk = result.wordsRemoved >= minWordsRemoved;
    const bool sizeOk = maxWmSize <= 0 || wmLocations() <= maxWmSize;
    const bool countOk = !atLeastOne || transferredLocations > 0;
    if (wordsOk && sizeOk && countOk) break;
    const std::vector<int> before = intermediatesBefore(id);
    if (!moveToLtm(id)) break;
    ++transferredLocations;
    bool refused = false;
    for (int i : before) {
      if (immune.count(i)) break;
      if (!moveToLtm(i)) {
        refused = true;
        break;
      }
    }
    if (refused) break;
  }
  transferredTotal_ += transferredLocations;
  return result;
}

std::vector<int> Memory::intermediatesBefore(int id) const {
  std::vector<int> chain;
  for (int n = id;;) {
    int previous = 0;
    for (const auto& [to, link] : signatures_.at(n).getLinks()) {
      if (link.type() == Link::kNeighbor && to < n && wm_.count(to) && signatures_.at(to).isIntermediate()) previous = to;
    }
    if (!previous) break;
    chain.push_back(previous);
    n = previous;
  }
  return chain;
}

// Words of the retrieved locations that left the vocabulary, all locations of a retrieval at
// once, in one database read. A word whose descriptor is in the vocabulary bit for bit (it came
// back meanwhile as another word) is that word; the others come back with their ids. Found by
// the vocabulary's descriptor hash, not by a nearest-neighbour search per word: that search was
// most of Reactivation (Mem/MaxRetrieved locations of hundreds of words, one FLANN query each),
// only to test for a distance of zero.
void Memory::requantize(std::vector<Signature>& retrieved) {
  std::vector<int> missing;
  for (Signature& s : retrieved) {
    for (auto it = s.getWords().begin(); it != s.getWords().end(); it = s.getWords().upper_bound(it->first)) {
      if (!vocabulary_.word(it->first)) missing.push_back(it->first);
    }
  }
  std::sort(missing.begin(), missing.end());
  missing.erase(std::unique(missing.begin(), missing.end()), missing.end());
  std::map<int, int> reused;  // stored word id -> current word id
  if (!missing.empty()) {
    std::vector<vocabulary::VisualWord> back;
    for (db::StoredWord& stored : ltm_->loadWords(missing)) {
      if (const int current = vocabulary_.exactWord(stored.descriptor)) {
        reused.emplace(stored.id, current);
      } else {
        savedWords_.insert(stored.id);  // it comes from the LTM
        back.push_back({stored.id, std::move(stored.descriptor), {}});
      }
    }
    vocabulary_.addWords(std::move(back));
  }
  for (Signature& s : retrieved) {
    for (const auto& [from, to] : reused) {
      if (s.getWords().count(from)) s.changeWordsRef(from, to);  // marks it modified
    }
    for (auto it = s.getWords().begin(); it != s.getWords().end(); it = s.getWords().upper_bound(it->first)) {
      if (vocabulary_.word(it->first)) {
        vocabulary_.addReference(it->first, s.id(), static_cast<int>(s.getWords().count(it->first)));
      }
    }
  }
}

std::vector<int> Memory::retrieve(int id) {
  if (!ltm_) throw std::logic_error("Memory::retrieve: no long-term memory (database) is attached");
  std::vector<int> toLoad;
  if (options_.maxRetrieved == 0 || !signatures_.count(id)) return toLoad;
  // Breadth first from the hypothesis over the whole graph (RAM and LTM); at each depth the
  // neighbours in time (neighbour links) come before the neighbours in space (loop closures).
  std::set<int> seen{id};
  std::vector<int> frontier{id};
  std::vector<int> passed;  // intermediate nodes walked through, in LTM
  for (int d = 1; d <= options_.neighborhoodDepth && !frontier.empty() &&
                  static_cast<int>(toLoad.size()) < options_.maxRetrieved;
       ++d) {
    std::vector<int> inTime, inSpace;
    std::vector<int> expand = frontier;  // grows with the intermediate nodes walked through
    for (size_t k = 0; k < expand.size(); ++k) {
      const int n = expand[k];
      const Signature* s = signature(n);
      const std::multimap<int, Link> links = s ? s->getLinks() : ltm_->loadLinks(n);
      for (const auto& [to, link] : links) {
        if (to <= 0 || to == n || link.type() == Link::kVirtualClosure || !seen.insert(to).second) continue;
        if (isIntermediate(to)) {  // no distance: what lies beyond is at this depth
          if (!signatures_.count(to)) passed.push_back(to);
          expand.push_back(to);
          continue;
        }
        const bool time = link.type() == Link::kNeighbor || link.type() == Link::kNeighborMerged;
        (time ? inTime : inSpace).push_back(to);
      }
    }
    frontier = inTime;
    frontier.insert(frontier.end(), inSpace.begin(), inSpace.end());
    for (int n : frontier) {
      if (static_cast<int>(toLoad.size()) >= options_.maxRetrieved) break;
      if (!signatures_.count(n)) toLoad.push_back(n);
    }
  }
  // The intermediate nodes walked through come in the same read, not counted: they are no locations.
  toLoad.insert(toLoad.end(), passed.begin(), passed.end());
  std::vector<int> retrieved = retrieveIds(toLoad);
  retrieved.erase(std::remove_if(retrieved.begin(), retrieved.end(),
                                 [this](int r) { return signatures_.at(r).isIntermediate(); }),
                  retrieved.end());
  return retrieved;
}

std::vector<int> Memory::retrieveIds(const std::vector<int>& ids) {
  if (!ltm_) throw std::logic_error("Memory::retrieveIds: no long-term memory (database) is attached");
  std::vector<int> toLoad;
  for (int id : ids) {
    if (!signatures_.count(id)) toLoad.push_back(id);
  }
  std::vector<int> retrieved;
  std::vector<Signature> loaded = ltm_->loadNodes(toLoad);
  for (Signature& s : loaded) {
    s.setSaved(true);
    s.setModified(false);
    s.setLinksModified(false);
  }
  requantize(loaded);  // marks a location modified if a word id changed: saved again when it leaves
  for (Signature& s : loaded) {
    const int sid = s.id();
    const bool intermediate = s.isIntermediate();
    insertInRam(std::move(s));
    wm_[sid] = updateCounter_;
    retrieved.push_back(sid);
    if (intermediate && !std::binary_search(intermediateIds_.begin(), intermediateIds_.end(), sid)) {
      intermediateIds_.insert(std::upper_bound(intermediateIds_.begin(), intermediateIds_.end(), sid), sid);
    }
  }
  retrievedTotal_ += static_cast<int>(std::count_if(retrieved.begin(), retrieved.end(),
                                                    [this](int r) { return !signatures_.at(r).isIntermediate(); }));
  return retrieved;
}

}  // namespace rtabmap::memory

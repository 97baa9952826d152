#include "rtabmap_core/memory/Memory.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/GravityLink.h"
#include "rtabmap_core/memory/LandmarkLinks.h"
#include "rtabmap_core/vocabulary/Similarity.h"

namespace rtabmap::memory {

namespace {

// Said once per doubling of the locations held in RAM only (STM excluded), not at every update.
void warnHeldInRam(size_t held, const std::string& cause) {
  if ((held & (held - 1)) != 0) return;
  RTABMAP_ERROR("long-term memory: the database takes no more writes; " << held
                << " location(s) are kept in RAM only (lost if the process ends before they can be saved): "
                << cause);
}

}  // namespace

MemoryOptions MemoryOptions::fromParameters(const ParametersMap& p) {
  MemoryOptions o;
  o.stmSize = Parameters::getInt(p, Parameters::kMemSTMSize());
  o.rehearsalSimilarity = Parameters::getFloat(p, Parameters::kMemRehearsalSimilarity());
  o.recentWmRatio = Parameters::getFloat(p, Parameters::kMemRecentWmRatio());
  o.transferSortingByWeightId = Parameters::getBool(p, Parameters::kMemTransferSortingByWeightId());
  o.rehearsalIdUpdatedToNewOne = Parameters::getBool(p, Parameters::kMemRehearsalIdUpdatedToNewOne());
  o.badSignaturesIgnored = Parameters::getBool(p, Parameters::kMemBadSignaturesIgnored());
  o.maxFeatures = Parameters::getInt(p, Parameters::kKpMaxFeatures());
  o.badSignRatio = Parameters::getFloat(p, Parameters::kKpBadSignRatio());
  o.tfIdf = Parameters::getBool(p, Parameters::kKpTfIdfLikelihoodUsed());
  o.maxRetrieved = Parameters::getInt(p, Parameters::kRtabmapMaxRetrieved());
  o.neighborhoodDepth =
      std::max(0, static_cast<int>(Parameters::getNumberList(p, Parameters::kBayesPredictionLC()).size()) - 2);
  o.incremental = Parameters::getBool(p, Parameters::kMemIncrementalMemory());
  o.stillLinear = Parameters::getFloat(p, Parameters::kRGBDLinearUpdate());
  o.stillAngular = Parameters::getFloat(p, Parameters::kRGBDAngularUpdate());
  o.rehearsalWeightIgnoredWhileMoving = Parameters::getBool(p, Parameters::kMemRehearsalWeightIgnoredWhileMoving());
  o.useOdomGravity = Parameters::getBool(p, Parameters::kMemUseOdomGravity());
  o.reduceGraph = Parameters::getBool(p, Parameters::kMemReduceGraph());
  o.rawDescriptorsKept = Parameters::getBool(p, Parameters::kMemRawDescriptorsKept());
  o.vocabulary = vocabulary::VocabularyOptions::fromParameters(p);
  std::string why;
  if (!o.IsValid(&why)) throw ParameterError(why);
  return o;
}

bool MemoryOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (stmSize < 0) return fail(Parameters::kMemSTMSize() + " must be >= 0");
  if (recentWmRatio < 0.f || recentWmRatio > 1.f) return fail(Parameters::kMemRecentWmRatio() + " must be in [0, 1]");
  if (badSignRatio < 0.f) return fail(Parameters::kKpBadSignRatio() + " must be >= 0");
  if (maxRetrieved < 0) return fail(Parameters::kRtabmapMaxRetrieved() + " must be >= 0");
  if (neighborhoodDepth < 0) return fail("neighbourhood depth must be >= 0");
  if (!(stillLinear >= 0.f) || !(stillAngular >= 0.f)) {
    return fail(Parameters::kRGBDLinearUpdate() + " and " + Parameters::kRGBDAngularUpdate() + " must be >= 0");
  }
  return vocabulary.IsValid(why);
}

Memory::Memory(const MemoryOptions& options, db::Database* ltm)
    : options_(options), ltm_(ltm), vocabulary_(options.vocabulary) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("Memory: " + why);
  if (ltm_) {
    // A new session continues the ids of the database (multi-session maps share id spaces).
    lastId_ = ltm_->lastNodeId();
    vocabulary_.setLastWordId(ltm_->lastWordId());
    intermediateIds_ = ltm_->intermediateNodeIds();
  }
}

Memory::~Memory() = default;

bool Memory::isIntermediate(int id) const {
  auto it = signatures_.find(id);
  if (it != signatures_.end()) return it->second.isIntermediate();
  return std::binary_search(intermediateIds_.begin(), intermediateIds_.end(), id);
}

int Memory::wmLocations() const {
  int inStm = 0;
  for (int id : stm_) inStm += signatures_.at(id).isIntermediate() ? 1 : 0;
  return static_cast<int>(wm_.size()) - (intermediatesInRam_ - inStm);
}

void Memory::insertInRam(Signature&& s) {
  if (s.isIntermediate()) ++intermediatesInRam_;
  const int id = s.id();
  signatures_.emplace(id, std::move(s));
}

void Memory::eraseFromRam(int id) {
  auto it = signatures_.find(id);
  if (it == signatures_.end()) return;
  if (it->second.isIntermediate()) --intermediatesInRam_;
  signatures_.erase(it);
}

Signature& Memory::at(int id) {
  auto it = signatures_.find(id);
  if (it == signatures_.end()) throw std::out_of_range("Memory: location " + std::to_string(id) + " is not in STM or WM");
  return it->second;
}

const Signature* Memory::signature(int id) const {
  auto it = signatures_.find(id);
  return it == signatures_.end() ? nullptr : &it->second;
}

Signature* Memory::mutableSignature(int id) {
  auto it = signatures_.find(id);
  return it == signatures_.end() ? nullptr : &it->second;
}

MemorySummary Memory::summary() const {
  MemorySummary s;
  s.wmSize = wmLocations();
  s.stmSize = static_cast<int>(stm_.size() + wm_.size()) - intermediatesInRam_ - s.wmSize;
  s.intermediatesInRam = intermediatesInRam_;
  s.vocabularySize = static_cast<int>(vocabulary_.size());
  s.lastLocationId = lastId_;
  s.lastGlobalLoopClosureId = lastGlobalLoopClosureId_;
  s.transferredTotal = transferredTotal_;
  s.retrievedTotal = retrievedTotal_;
  s.reducedTotal = reducedTotal_;
  return s;
}

// Algorithm 2: the strongest Kp/MaxFeatures keypoints (by detector response) make the words.
void Memory::selectStrongest(LocationInput& in) const {
  if (options_.maxFeatures < 0) {
    in.keypoints.clear();
    in.descriptors = cv::Mat();
    in.points3D.clear();
    return;
  }
  const size_t n = in.keypoints.size();
  if (options_.maxFeatures == 0 || n <= static_cast<size_t>(options_.maxFeatures)) return;
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return in.keypoints[a].response > in.keypoints[b].response; });
  order.resize(options_.maxFeatures);
  std::sort(order.begin(), order.end());  // keep the image order
  std::vector<cv::KeyPoint> kpts;
  std::vector<cv::Point3f> pts;
  cv::Mat desc(static_cast<int>(order.size()), in.descriptors.cols, in.descriptors.type());
  for (size_t i = 0; i < order.size(); ++i) {
    kpts.push_back(in.keypoints[order[i]]);
    if (!in.points3D.empty()) pts.push_back(in.points3D[order[i]]);
    in.descriptors.row(order[i]).copyTo(desc.row(static_cast<int>(i)));
  }
  in.keypoints.swap(kpts);
  in.points3D.swap(pts);
  in.descriptors = desc;
}

bool Memory::isBadSignature(int words) const {
  if (words == 0) return true;
  if (wordsLocations_ == 0) return false;
  return words < options_.badSignRatio * (wordsSum_ / static_cast<double>(wordsLocations_));
}

size_t Memory::locationsMemoryUsed() const {
  size_t bytes = 0;
  for (const auto& entry : signatures_) bytes += entry.second.memoryUsed();
  return bytes;
}

AddResult Memory::addLocation(const LocationInput& rawInput) {
  ++updateCounter_;
  LocationInput in = rawInput;
  if (in.descriptors.rows != static_cast<int>(in.keypoints.size())) {
    throw std::invalid_argument("Memory::addLocation: " + std::to_string(in.descriptors.rows) +
                                " descriptors for " + std::to_string(in.keypoints.size()) + " keypoints");
  }
  if (!in.points3D.empty() && in.points3D.size() != in.keypoints.size()) {
    throw std::invalid_argument("Memory::addLocation: points3D and keypoints differ in size");
  }
  selectStrongest(in);

  AddResult result;
  if (in.id < 0 || (in.id != 0 && in.id <= lastId_)) {
    throw std::invalid_argument("Memory::addLocation: id " + std::to_string(in.id) + " is not above the last location's " +
                                std::to_string(lastId_));
  }
  const int id = in.id != 0 ? in.id : lastId_ + 1;
  if (in.intermediate) return addIntermediate(in, id);
  const std::vector<int> wordIds = vocabulary_.quantize(in.descriptors, id);
  std::multimap<int, int> words;
  for (size_t i = 0; i < wordIds.size(); ++i) {
    if (wordIds[i] > 0) words.emplace(wordIds[i], static_cast<int>(i));
  }
  result.words = static_cast<int>(words.size());
  result.newWords = vocabulary_.summary().lastNewWords;
  result.badSignature = isBadSignature(result.words);
  if (result.badSignature && options_.badSignaturesIgnored) {
    // Not added at all: its references and the words only it had go away.
    removeFromVocabulary(id, words);
    return result;
  }
  if (result.words > 0) {
    wordsSum_ += result.words;
    ++wordsLocations_;
  }

  Signature fresh(id, in.mapId, 0, in.stamp, std::string(), in.pose, in.data.groundTruth(), in.data);
  if (!words.empty()) {
    std::vector<cv::KeyPoint> kpts;
    std::vector<cv::Point3f> pts;
    std::vector<int> rows;
    // Keypoints without a word (fixed vocabulary) are dropped so indices stay dense.
    for (size_t i = 0; i < wordIds.size(); ++i) {
      if (wordIds[i] <= 0) continue;
      rows.push_back(static_cast<int>(i));
    }
    std::multimap<int, int> dense;
    cv::Mat desc;
    if (options_.rawDescriptorsKept) desc.create(static_cast<int>(rows.size()), in.descriptors.cols, in.descriptors.type());
    for (size_t k = 0; k < rows.size(); ++k) {
      dense.emplace(wordIds[rows[k]], static_cast<int>(k));
      kpts.push_back(in.keypoints[rows[k]]);
      if (!in.points3D.empty()) pts.push_back(in.points3D[rows[k]]);
      if (!desc.empty()) in.descriptors.row(rows[k]).copyTo(desc.row(static_cast<int>(k)));
    }
    fresh.setWords(dense, kpts, pts, desc);
  }
  fresh.setBadSignature(result.badSignature);
  if (std::optional<Link> gravity = gravityLinkOf(id, in.pose, in.data.imu(), options_.useOdomGravity)) {
    fresh.addLink(*gravity);
  }
  std::vector<std::string> refused;
  for (const Link& l : landmarkLinksOf(id, in.data.landmarks(), &refused)) fresh.addLink(l);
  for (const std::string& r : refused) RTABMAP_WARN(r);

  const int previousId = linkToPrevious(fresh, in, result);
  previousOfLast_ = previousId;
  result.id = id;
  lastId_ = id;
  insertInRam(std::move(fresh));
  auto inserted = signatures_.find(id);
  stm_.insert(id);
  // Rehearsal merges consecutive views of one place, never across maps (a new session's first
  // location is not the same place as the previous session's last, whatever it looks like).
  const Signature* previous = previousId ? &signatures_.at(previousId) : nullptr;
  if (previous && previous->mapId() == inserted->second.mapId() && options_.rehearsalSimilarity < 1.0f &&
      result.rehearsalSimilarity >= options_.rehearsalSimilarity && !previous->isBadSignature() &&
      !inserted->second.isBadSignature()) {
    if (result.moving) {
      rehearseWhileMoving(signatures_.at(previousId), inserted->second);
    } else {
      rehearse(signatures_.at(previousId), inserted->second, result);
    }
  }
  previousId_ = result.id;
  moveStmOverflowToWm(result);
  return result;
}

// Neighbour link to the previous location (odometry between them, identity without poses):
// the location the last update left (the kept one after a rehearsal merge), if still in RAM.
int Memory::linkToPrevious(Signature& fresh, const LocationInput& in, AddResult& result) {
  const int previousId = signatures_.count(previousId_) ? previousId_ : 0;
  if (!previousId) return 0;
  Signature& previous = at(previousId);
  Transform t = Transform::Identity();
  if (!previous.getPose().isNull() && !fresh.getPose().isNull()) t = previous.getPose().inverse() * fresh.getPose();
  if (previous.mapId() == fresh.mapId()) {
    addLinkBetween(previous, fresh, Link(previousId, fresh.id(), Link::kNeighbor, t, in.odomInformation));
  }
  result.rehearsalSimilarity = vocabulary::similarity(previous.getWords(), fresh.getWords());
  result.moving = isMoving(previous, fresh);
  return previousId;
}

// An intermediate node (Rtabmap/CreateIntermediateNodes): the pose and data of a frame between
// two updates, linked in the chain of neighbours. No words, so nothing to rehearse or detect;
// it waits in STM for the location that follows it and goes to WM and the LTM before it.
AddResult Memory::addIntermediate(const LocationInput& in, int id) {
  AddResult result;
  result.badSignature = true;
  Signature fresh(id, in.mapId, Signature::kIntermediateWeight, in.stamp, std::string(), in.pose,
                  in.data.groundTruth(), in.data);
  fresh.setBadSignature(true);
  if (std::optional<Link> gravity = gravityLinkOf(id, in.pose, in.data.imu(), options_.useOdomGravity)) {
    fresh.addLink(*gravity);
  }
  previousOfLast_ = linkToPrevious(fresh, in, result);
  result.id = id;
  lastId_ = id;
  insertInRam(std::move(fresh));
  stm_.insert(id);
  intermediateIds_.push_back(id);  // ids only grow: the vector stays sorted
  previousId_ = id;
  moveStmOverflowToWm(result);
  return result;
}

// T-RO 2013, III-C: the new location and the previous one are the same place; one of them
// remains with weight (previous weight + new weight + 1). By default the previous keeps its id
// and the new one is dropped; with Mem/RehearsalIdUpdatedToNewOne the new one stays and takes
// over the previous one's links, unless the previous one is already saved (Mem/STMSize 0 saves
// a location as it enters WM): the database keeps every location it acknowledged, so that one
// stays and the new one goes, as by default.
void Memory::rehearse(Signature& previous, Signature& fresh, AddResult& result) {
  const int weight = previous.weight() + fresh.weight() + 1;
  const bool newIdKept = options_.rehearsalIdUpdatedToNewOne && !previous.isSaved();
  Signature& removed = newIdKept ? previous : fresh;
  Signature& kept = newIdKept ? fresh : previous;
  const int removedId = removed.id();
  removeLinkBetween(kept, removed);
  // The removed location's other links now end on the kept one (its own gravity link stays
  // with it: the kept location has one of its own).
  for (const auto& [to, link] : std::multimap<int, Link>(removed.getLinks())) {
    if (to == removedId) continue;
    if (link.type() == Link::kLandmark) {
      // A landmark only the removed location saw stays seen, from the kept one's pose.
      if (kept.hasLink(to, Link::kLandmark)) continue;
      Link moved = link;
      moved.setFrom(kept.id());
      if (!kept.getPose().isNull() && !removed.getPose().isNull()) {
        moved.setTransform(kept.getPose().inverse() * removed.getPose() * link.transform());
      }
      kept.addLink(moved);
      continue;
    }
    Link moved = link;
    moved.setFrom(kept.id());
    Signature* other = mutableSignature(to);
    if (other) {
      other->removeLink(removedId, link.type());
      addLinkBetween(kept, *other, moved);
      continue;
    }
    // The other end went to the LTM meanwhile (a loop closure of a location still in STM): its
    // saved row links to the removed location, which will never be saved; the LTM's link moves
    // too, or the kept location would lose the constraint and the LTM keep a dangling one.
    // (A temporary link, of a planned path, is never saved.)
    kept.addLink(moved);
    if (ltm_ && options_.incremental && link.type() != Link::kTemporary) {
      ltm_->removeLink(to, removedId, link.type());
      ltm_->saveLink(moved);
    }
  }
  kept.setWeight(weight);
  // Words only the removed location had leave (if saved, the LTM still has them).
  removeFromVocabulary(removedId, removed.getWords());
  result.merged = true;
  result.mergedWith = removedId;
  result.id = kept.id();
  stm_.erase(removedId);
  wm_.erase(removedId);  // with Mem/STMSize 0 the previous location is already in WM
  eraseFromRam(removedId);
}

bool Memory::isMoving(const Signature& previous, const Signature& fresh) const {
  if (previous.getPose().isNull() || fresh.getPose().isNull()) return false;
  const Transform motion = previous.getPose().inverse() * fresh.getPose();
  return motion.getNorm() > options_.stillLinear || std::fabs(motion.getAngle()) > options_.stillAngular;
}

// Metric SLAM: the same view from a new pose. Both locations stay (the graph needs the pose of
// each); the place's weight moves to the newer one, which memory management must now keep,
// and the older one can go to the LTM first (the original's rule for a moving robot).
void Memory::rehearseWhileMoving(Signature& previous, Signature& fresh) {
  if (options_.rehearsalWeightIgnoredWhileMoving) return;
  fresh.setWeight(fresh.weight() + previous.weight() + 1);
  previous.setWeight(0);
}

void Memory::removeLastLocation() {
  auto it = signatures_.find(lastId_);
  if (it == signatures_.end()) throw std::logic_error("Memory::removeLastLocation: the last location is not in RAM");
  Signature& s = it->second;
  if (s.isSaved()) throw std::logic_error("Memory::removeLastLocation: location " + std::to_string(lastId_) + " is already saved");
  for (const auto& [to, link] : s.getLinks()) {
    (void)link;
    auto other = signatures_.find(to);
    if (other != signatures_.end() && to != lastId_) other->second.removeLink(lastId_);
  }
  const int words = static_cast<int>(s.getWords().size());
  removeFromVocabulary(lastId_, s.getWords());
  if (words > 0 && wordsLocations_ > 0) {
    wordsSum_ -= words;
    --wordsLocations_;
  }
  if (s.isIntermediate() && !intermediateIds_.empty() && intermediateIds_.back() == lastId_) intermediateIds_.pop_back();
  stm_.erase(lastId_);
  wm_.erase(lastId_);
  eraseFromRam(lastId_);
  previousId_ = signatures_.count(previousOfLast_) ? previousOfLast_ : 0;
}

void Memory::addLink(const Link& link) {
  addLinkBetween(at(link.from()), at(link.to()), link);
}

bool Memory::removeLink(int from, int to, Link::Type type) {
  Signature* a = signatures_.count(from) ? &signatures_.at(from) : nullptr;
  Signature* b = signatures_.count(to) ? &signatures_.at(to) : nullptr;
  if (!a && !b) return false;
  if (a && b) {
    removeLinkBetween(*a, *b, type);
  } else {
    (a ? a : b)->removeLink(a ? to : from, type);
  }
  // The saved end's links in the LTM would bring the link back on retrieval.
  if (ltm_ && options_.incremental && ((a && a->isSaved()) || (b && b->isSaved()) || !a || !b)) {
    ltm_->removeLink(from, to, type);
  }
  return true;
}

bool Memory::setLabel(int id, const std::string& label) {
  auto it = signatures_.find(id);
  if (it != signatures_.end()) {
    it->second.setLabel(label);
    return true;
  }
  if (!ltm_ || !ltm_->loadNode(id, db::LoadOptions::nodeOnly())) return false;
  if (!options_.incremental) throw std::logic_error("Memory::setLabel: localization mode does not modify the map");
  db::NodeUpdate update;
  update.id = id;
  update.label = label;
  ltm_->updateNode(update);
  return true;
}

bool Memory::setUserData(int id, const cv::Mat& data, std::string* why) {
  auto fail = [why](const std::string& problem) {
    if (why) *why = problem;
    return false;
  };
  auto it = signatures_.find(id);
  if (it == signatures_.end()) return fail("node " + std::to_string(id) + " is not in memory");
  if (!options_.incremental) return fail("localization mode does not modify the map");
  if (it->second.isSaved()) return fail("node " + std::to_string(id) + " is already saved");
  SensorData& sensors = it->second.sensorData();
  if (!sensors.userDataRaw().empty() || !sensors.userDataCompressed().empty()) {
    return fail("node " + std::to_string(id) + " already has user data");
  }
  sensors.setUserData(data);
  sensors.setCompressed(sensors.imageCompressed(), sensors.depthOrRightCompressed(), sensors.laserScanCompressed(),
                        codec::compressData(data));
  return true;
}

// Intermediate nodes do not count: STM holds the Mem/STMSize newest locations and the
// intermediate nodes among them, which go to WM right before the location that follows them.
void Memory::moveStmOverflowToWm(AddResult& result) {
  int locations = 0;
  for (int id : stm_) locations += signatures_.at(id).isIntermediate() ? 0 : 1;
  while (locations > options_.stmSize) {
    const int oldest = *stm_.begin();
    if (!signatures_.at(oldest).isIntermediate()) --locations;
    if (const int into = options_.reduceGraph ? reductionTarget(signatures_.at(oldest)) : 0) {
      reduce(oldest, into, result.relinked);
      result.reduced.emplace_back(oldest, into);
      continue;
    }
    stm_.erase(stm_.begin());
    wm_[oldest] = updateCounter_;
    if (ltm_) saveToLtm(at(oldest));
  }
}

// A location the LTM refuses (its writer stopped: disk full, I/O error) stays in RAM, unsaved:
// mapping goes on, transfer keeps it (see transfer()), and saveAll() tries it again at the
// end. The writer logged the cause; what is at stake is said here.
void Memory::saveToLtm(Signature& s) {
  if (!options_.incremental) return;  // localization: the saved map is never modified
  std::vector<db::StoredWord> newWords;
  for (auto it = s.getWords().begin(); it != s.getWords().end(); it = s.getWords().upper_bound(it->first)) {
    if (savedWords_.count(it->first)) continue;
    const vocabulary::VisualWord* w = vocabulary_.word(it->first);
    if (!w) continue;
    newWords.push_back({w->id, w->descriptor});
  }
  std::vector<int> newWordIds;
  for (const db::StoredWord& w : newWords) newWordIds.push_back(w.id);
  try {
    ltm_->saveNode(s, std::move(newWords));
  } catch (const DatabaseError& e) {
    const size_t unsaved = static_cast<size_t>(std::count_if(
        signatures_.begin(), signatures_.end(), [](const auto& entry) { return !entry.second.isSaved(); }));
    warnHeldInRam(unsaved > stm_.size() ? unsaved - stm_.size() : 1, e.what());
    return;
  }
  // Only now: words of a refused location must go with it when it is saved later.
  savedWords_.insert(newWordIds.begin(), newWordIds.end());
  s.setSaved(true);
  s.setModified(false);
  s.setLinksModified(false);
}

int Memory::removeFromVocabulary(int id, const std::multimap<int, int>& words) {
  vocabulary_.removeReferences(id, words);
  int removed = 0;
  for (auto it = words.begin(); it != words.end(); it = words.upper_bound(it->first)) {
    const vocabulary::VisualWord* w = vocabulary_.word(it->first);
    if (w && w->references.empty()) {
      vocabulary_.removeWord(it->first);
      // Forgotten with the word: the set would otherwise hold every word of the map (tens of
      // bytes each, hundreds of thousands in hours). A retrieval that brings the word back
      // marks it saved again (requantize).
      savedWords_.erase(it->first);
      ++removed;
    }
  }
  return removed;
}

std::map<int, float> Memory::computeLikelihood(int id) const {
  const auto scores = likelihoodScores(id);
  return std::map<int, float>(scores.begin(), scores.end());
}

std::vector<std::pair<int, float>> Memory::likelihoodScores(int id) const {
  const Signature* s = signature(id);
  if (!s) throw std::out_of_range("Memory::computeLikelihood: location " + std::to_string(id) + " is not in RAM");
  std::vector<std::pair<int, int>> candidates;  // sorted by id, as wm_ is
  candidates.reserve(wm_.size());
  for (const auto& [wmId, age] : wm_) {
    (void)age;
    const Signature& c = signatures_.at(wmId);
    if (wmId != id && !c.isBadSignature()) candidates.emplace_back(wmId, static_cast<int>(c.getWords().size()));
  }
  return vocabulary::computeLikelihoodScores(vocabulary_, s->getWords(), candidates,
                                             static_cast<int>(signatures_.size()) - intermediatesInRam_,
                                             options_.tfIdf);
}

std::map<int, int> Memory::neighbors(int id, int maxDepth) const {
  std::map<int, int> depth;
  if (!signatures_.count(id)) return depth;
  depth[id] = 0;
  std::vector<int> frontier{id};
  std::set<int> passed;  // intermediate nodes walked through
  for (int d = 1; d <= maxDepth && !frontier.empty(); ++d) {
    std::vector<int> next;
    std::vector<int> expand = frontier;  // grows with the intermediate nodes walked through
    for (size_t k = 0; k < expand.size(); ++k) {
      const int n = expand[k];
      for (const auto& [to, link] : signatures_.at(n).getLinks()) {
        if (to <= 0 || to == n || link.type() == Link::kVirtualClosure || !signatures_.count(to)) continue;
        if (signatures_.at(to).isIntermediate() && to != id) {
          if (passed.insert(to).second) expand.push_back(to);  // same depth beyond it
          continue;
        }
        if (depth.emplace(to, d).second) next.push_back(to);
      }
    }
    frontier.swap(next);
  }
  return depth;
}

void Memory::addLoopClosure(const Link& link) {
  Signature& a = at(link.from());
  Signature& b = at(link.to());
  addLinkBetween(a, b, link);
  Signature& newer = a.id() > b.id() ? a : b;
  Signature& older = a.id() > b.id() ? b : a;
  if (!newer.isIntermediate() && !older.isIntermediate()) {  // -1 marks them, it is no weight
    newer.setWeight(newer.weight() + older.weight());
    older.setWeight(0);
  }
  lastGlobalLoopClosureId_ = std::max(lastGlobalLoopClosureId_, newer.id());
}

// A stopped writer (disk full...) is not this update's failure: the writer logged why, what it
// could not write is still readable from its queue, and saveToLtm() keeps refused locations
// in RAM. Throwing here would end every later update (and the SLAM node with it).
void Memory::joinLtmWriter() {
  if (!ltm_) return;
  try {
    ltm_->flush();
  } catch (const DatabaseError&) {
  }
}

void Memory::saveAll() {
  if (!ltm_) return;
  for (auto& [id, s] : signatures_) {
    if (!s.isSaved() || s.isModified() || s.isLinksModified()) saveToLtm(s);
  }
  ltm_->flush();
}

}  // namespace rtabmap::memory

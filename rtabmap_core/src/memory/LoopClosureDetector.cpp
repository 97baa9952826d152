#include "rtabmap_core/memory/LoopClosureDetector.h"
#include "rtabmap_core/memory/ProcessMemory.h"

#include <chrono>
#include <stdexcept>

#include "rtabmap_core/common/Error.h"

namespace rtabmap::memory {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

}  // namespace

LoopClosureDetectorOptions LoopClosureDetectorOptions::fromParameters(const ParametersMap& p) {
  LoopClosureDetectorOptions o;
  o.timeThr = Parameters::getFloat(p, Parameters::kRtabmapTimeThr());
  o.memoryThr = Parameters::getInt(p, Parameters::kRtabmapMemoryThr());
  o.memory = MemoryOptions::fromParameters(p);
  o.bayes = bayes::BayesFilterOptions::fromParameters(p);
  o.hypothesis = bayes::HypothesisOptions::fromParameters(p);
  o.epipolar = EpipolarCheckOptions::fromParameters(p);
  std::string why;
  if (!o.IsValid(&why)) throw ParameterError(why);
  return o;
}

bool LoopClosureDetectorOptions::IsValid(std::string* why) const {
  if (timeThr < 0.0f || memoryThr < 0) {
    if (why) *why = Parameters::kRtabmapTimeThr() + " and " + Parameters::kRtabmapMemoryThr() + " must be >= 0";
    return false;
  }
  return memory.IsValid(why) && bayes.IsValid(why) && hypothesis.IsValid(why) && epipolar.IsValid(why);
}

LoopClosureDetector::LoopClosureDetector(const LoopClosureDetectorOptions& options, db::Database* ltm)
    : options_(options), memory_(options.memory, ltm), filter_(options.bayes), ltm_(ltm) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("LoopClosureDetector: " + why);
}

LoopClosureUpdate LoopClosureDetector::process(const LocationInput& input, bool keepPosterior) {
  const auto start = Clock::now();
  LoopClosureUpdate u;
  const size_t vocabularyAtStart = memory_.vocabulary().size();
  const AddResult added = addLocation(input, u);
  detect(added.id, u, keepPosterior);
  if (verifyEpipolar(added.id, u)) {
    acceptLoopClosure(Link(added.id, u.highest.id, Link::kGlobalClosure, Transform::Identity()));
    u.loopClosureId = u.highest.id;
  }
  std::set<int> immune;
  retrieveNeighbors(u.highest.id, u, immune);
  manageMemory(immune, msSince(start), vocabularyAtStart, u);
  releaseFreedHeap();  // what this update freed goes back to the system (ProcessMemory.h)
  u.totalMs = msSince(start);
  return u;
}

AddResult LoopClosureDetector::addLocation(const LocationInput& input, LoopClosureUpdate& u) {
  const auto t = Clock::now();
  memory_.joinLtmWriter();  // the previous update's writes are done before this one starts
  const AddResult added = memory_.addLocation(input);
  // Mem/ReduceGraph: the transition rows through a location merged away are stale.
  if (!added.relinked.empty()) linksChanged(added.relinked);
  u.id = added.id;
  u.merged = added.merged;
  u.words = added.words;
  u.newWords = added.newWords;
  u.memoryUpdateMs = msSince(t);
  return added;
}

void LoopClosureDetector::detect(int id, LoopClosureUpdate& u, bool keepPosterior, bool keepLikelihood) {
  // A location merged by rehearsal is still the current place (T-RO 2013, III-C: L_c is merged
  // into L_t, which goes on to the Bayes filter): only bad signatures skip detection.
  const Signature* s = memory_.signature(id);
  if (!s || s->isBadSignature() || memory_.wm().empty()) return;
  const auto neighbors = [this](int node, int depth) { return memory_.neighbors(node, depth); };
  auto t = Clock::now();
  const bayes::Scores likelihood = bayes::adjustLikelihoodScores(memory_.likelihoodScores(id));
  u.likelihoodMs = msSince(t);
  if (keepLikelihood) u.likelihood = bayes::toMap(likelihood);
  t = Clock::now();
  const bayes::Scores& posterior = filter_.updateScores(likelihood, neighbors);
  u.posteriorMs = msSince(t);
  t = Clock::now();
  u.highest = bayes::selectHypothesisScores(posterior, options_.hypothesis, previousHypothesisValue_);
  previousHypothesisValue_ = u.highest.value;
  if (keepPosterior) u.posterior = bayes::toMap(posterior);
  u.hypothesisMs = msSince(t);
}

bool LoopClosureDetector::verifyEpipolar(int id, LoopClosureUpdate& u) const {
  if (!options_.epipolar.enabled || !u.highest.accepted) return u.highest.accepted;
  const Signature* query = memory_.signature(id);
  const Signature* candidate = memory_.signature(u.highest.id);
  if (!query || !candidate) return u.highest.accepted;  // detect() only proposes locations in RAM
  const EpipolarCheckSummary check = checkEpipolarGeometry(*query, *candidate, options_.epipolar);
  u.epipolarInliers = check.inliers;
  if (!check.accepted) {
    u.highest.accepted = false;
    u.highest.rejectedBecause = check.Summary();
  }
  return u.highest.accepted;
}

void LoopClosureDetector::acceptLoopClosure(const Link& link) {
  memory_.addLoopClosure(link);
  linksChanged({link.from(), link.to()});
}

void LoopClosureDetector::linksChanged(const std::set<int>& ids) {
  filter_.invalidateNeighborhood(ids, [this](int node, int depth) { return memory_.neighbors(node, depth); });
}

void LoopClosureDetector::retrieveNeighbors(int highestId, LoopClosureUpdate& u, std::set<int>& immune) {
  if (ltm_ && highestId > 0) {
    const auto t = Clock::now();
    u.retrieved = memory_.retrieve(highestId);
    // The hypothesis and its direct neighbours are where the robot is expected next: they stay
    // in WM with what was just retrieved. (Sparing the whole transition range would leave a
    // small WM nothing to transfer.)
    for (const auto& [id, depth] : memory_.neighbors(highestId, 1)) {
      (void)depth;
      immune.insert(id);
    }
    u.retrievalMs = msSince(t);
  }
  immune.insert(u.retrieved.begin(), u.retrieved.end());
}

void LoopClosureDetector::manageMemory(const std::set<int>& immune, double elapsedMs, size_t vocabularyAtStart,
                                       LoopClosureUpdate& u) {
  const bool overTime = options_.timeThr > 0.0f && elapsedMs > options_.timeThr;
  const bool overSize = options_.memoryThr > 0 && memory_.wmLocations() > options_.memoryThr;
  if (ltm_ && (overTime || overSize)) {
    const auto t = Clock::now();
    // As many words leave the vocabulary as entered it in this update (new and retrieved words).
    const size_t now = memory_.vocabulary().size();
    const int entered = now > vocabularyAtStart ? static_cast<int>(now - vocabularyAtStart) : 0;
    u.transferred = memory_.transfer(immune, entered, options_.memoryThr, overTime).transferred;
    u.transferMs = msSince(t);
  }
  const MemorySummary s = memory_.summary();
  u.wmSize = s.wmSize;
  u.stmSize = s.stmSize;
  u.vocabularySize = s.vocabularySize;
}

}  // namespace rtabmap::memory

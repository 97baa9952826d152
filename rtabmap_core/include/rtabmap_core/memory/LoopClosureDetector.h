#pragma once
// Appearance-based loop-closure detection with memory management: Algorithm 1 of T-RO 2013,
// one location per call. The SLAM pipeline (slam area) adds the metric parts around it; the
// appearance-only tool (rtabmap-console) uses it as is.
//
// One update: join the LTM writer, create the location (Algorithm 2, rehearsal), likelihood over
// WM (TF-IDF or eq. 1) adjusted by eq. 4, Bayes filter posterior, hypothesis selection and loop
// closure, retrieval of the highest hypothesis' neighbours (Algorithm 3), and, when the update
// took longer than Rtabmap/TimeThr or WM exceeds Rtabmap/MemoryThr, transfer (Algorithm 4).
#include <map>
#include <memory>
#include <vector>

#include "rtabmap_core/bayes/BayesFilter.h"
#include "rtabmap_core/bayes/Likelihood.h"
#include "rtabmap_core/memory/EpipolarCheck.h"
#include "rtabmap_core/memory/Memory.h"

namespace rtabmap::memory {

struct LoopClosureDetectorOptions {
  float timeThr = 0.0f;  // Rtabmap/TimeThr (ms, 0 = no limit)
  int memoryThr = 0;     // Rtabmap/MemoryThr (0 = no limit)
  MemoryOptions memory;
  bayes::BayesFilterOptions bayes;
  bayes::HypothesisOptions hypothesis;
  EpipolarCheckOptions epipolar;  // VhEp/*: appearance-only verification

  static LoopClosureDetectorOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
};

struct LoopClosureUpdate {
  int id = 0;                 // location holding this update's data (0: bad signature dropped)
  bool merged = false;        // rehearsal merged it into the previous location
  int loopClosureId = 0;      // accepted loop closure (0: none)
  bayes::Hypothesis highest;  // highest hypothesis, accepted or not
  int epipolarInliers = -1;   // the epipolar check's inliers (-1: not checked)
  std::vector<int> retrieved, transferred;
  int words = 0, newWords = 0, wmSize = 0, stmSize = 0, vocabularySize = 0;
  // Timings (ms), the names of the original's statistics.
  double memoryUpdateMs = 0, likelihoodMs = 0, posteriorMs = 0, hypothesisMs = 0;
  double retrievalMs = 0, transferMs = 0, totalMs = 0;
  std::map<int, float> posterior;   // kept only when asked (statistics)
  std::map<int, float> likelihood;  // adjusted (eq. 4), kept only when asked
};

class LoopClosureDetector {
 public:
  // ltm may be null: no transfer or retrieval (WM grows without bound).
  LoopClosureDetector(const LoopClosureDetectorOptions& options, db::Database* ltm);

  // The whole of Algorithm 1 (appearance only): the stages below in order, a selected
  // hypothesis verified by epipolar geometry if VhEp/Enabled, then linked (identity transform).
  LoopClosureUpdate process(const LocationInput& input, bool keepPosterior = false);

  // --- The stages of process(), for the SLAM pipeline, which verifies a hypothesis by
  // registration before linking it and adds its own links and immunities between them. ---
  // Joins the LTM writer of the previous update, then creates the location (Algorithm 2,
  // rehearsal). Fills u.id, merged, words, newWords, memoryUpdateMs.
  AddResult addLocation(const LocationInput& input, LoopClosureUpdate& u);
  // Likelihood over WM (adjusted by eq. 4), posterior, hypothesis selection for location `id`
  // (no link is made). Fills u.highest, the timings, and the posterior and the likelihood if
  // asked. Nothing happens for a bad signature or an empty WM (u.highest stays empty).
  void detect(int id, LoopClosureUpdate& u, bool keepPosterior, bool keepLikelihood = false);
  // Appearance-only verification of an accepted hypothesis (VhEp/Enabled; nothing otherwise):
  // a refused one is no longer accepted and says why in u.highest.rejectedBecause. Returns
  // u.highest.accepted.
  bool verifyEpipolar(int id, LoopClosureUpdate& u) const;
  // An accepted loop closure is linked: the weight rule and the filter's neighbourhood.
  void acceptLoopClosure(const Link& link);
  // Links were added or removed around these locations (proximity, rejected links): the
  // filter's transition rows there are recomputed.
  void linksChanged(const std::set<int>& ids);
  // Algorithm 3 around the highest hypothesis; adds the hypothesis, its direct neighbours and
  // the retrieved locations to `immune`. Fills u.retrieved, u.retrievalMs.
  void retrieveNeighbors(int highestId, LoopClosureUpdate& u, std::set<int>& immune);
  // Algorithm 4 when the update (started at `elapsedMs` ago) is over Rtabmap/TimeThr or WM over
  // Rtabmap/MemoryThr: as many words leave as entered since `vocabularyAtStart`. Fills
  // u.transferred, u.transferMs and the memory sizes.
  void manageMemory(const std::set<int>& immune, double elapsedMs, size_t vocabularyAtStart, LoopClosureUpdate& u);

  const Memory& memory() const { return memory_; }
  Memory& memory() { return memory_; }
  const bayes::BayesFilter& filter() const { return filter_; }
  const LoopClosureDetectorOptions& options() const { return options_; }

 private:
  LoopClosureDetectorOptions options_;
  Memory memory_;
  bayes::BayesFilter filter_;
  db::Database* ltm_;
  float previousHypothesisValue_ = 0.0f;
};

}  // namespace rtabmap::memory

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
#include "rtabmap_core/memory/Memory.h"

namespace rtabmap::memory {

struct LoopClosureDetectorOptions {
  float timeThr = 0.0f;  // Rtabmap/TimeThr (ms, 0 = no limit)
  int memoryThr = 0;     // Rtabmap/MemoryThr (0 = no limit)
  MemoryOptions memory;
  bayes::BayesFilterOptions bayes;
  bayes::HypothesisOptions hypothesis;

  static LoopClosureDetectorOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
};

struct LoopClosureUpdate {
  int id = 0;                 // location holding this update's data (0: bad signature dropped)
  bool merged = false;        // rehearsal merged it into the previous location
  int loopClosureId = 0;      // accepted loop closure (0: none)
  bayes::Hypothesis highest;  // highest hypothesis, accepted or not
  std::vector<int> retrieved, transferred;
  int words = 0, newWords = 0, wmSize = 0, stmSize = 0, vocabularySize = 0;
  // Timings (ms), the names of the original's statistics.
  double memoryUpdateMs = 0, likelihoodMs = 0, posteriorMs = 0, hypothesisMs = 0;
  double retrievalMs = 0, transferMs = 0, totalMs = 0;
  std::map<int, float> posterior;   // kept only when asked (statistics)
};

class LoopClosureDetector {
 public:
  // ltm may be null: no transfer or retrieval (WM grows without bound).
  LoopClosureDetector(const LoopClosureDetectorOptions& options, db::Database* ltm);

  LoopClosureUpdate process(const LocationInput& input, bool keepPosterior = false);

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

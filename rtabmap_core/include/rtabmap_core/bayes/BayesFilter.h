#pragma once
// The discrete Bayes filter of loop-closure detection (T-RO 2013, section III-D, eq. 2):
//
//   p(S_t | L^t) = eta * p(L_t | S_t) * sum_i p(S_t | S_{t-1} = i) p(S_{t-1} = i | L^{t-1})
//
// S_t is the hypothesis "the new location L_t closes a loop with Working-Memory location i",
// or kVirtualPlace (-1): "L_t is a new place". The likelihood p(L_t | S_t) comes adjusted by
// eq. 3-4 (see Likelihood.h); this class owns the transition model and the posterior.
//
// Transition model p(S_t | S_{t-1}) (the paper's, parameters Bayes/VirtualPlacePriorThr and
// Bayes/PredictionLC = [p0, p1, p2, ...]):
//   from the virtual place: stays virtual with VirtualPlacePriorThr (0.9); the rest is spread
//     uniformly over the Working-Memory locations;
//   from location j: goes to the virtual place with p0 (0.1); to j itself with p1 and to the
//     locations d links away with p(d+1), for d up to PredictionLC.size() - 2 (a discretised
//     Gaussian of sigma 1.6 over 16 neighbours by default); that part is normalised to 1 - p0
//     over the neighbours that are hypotheses now (neighbours in STM or LTM drop out).
//
// Cost: a row of the transition model depends only on the graph neighbourhood of j, so rows are
// cached and only those near added, removed or re-linked locations are recomputed
// (Bayes/FullPredictionUpdate recomputes all); the prediction is then linear in the WM size
// times the neighbourhood size. Everything runs on flat sorted vectors (Scores.h): at 20,000
// hypotheses the std::map version spent 30 ms per update walking and allocating tree nodes.
#include <functional>
#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "rtabmap_core/bayes/Scores.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap::bayes {

// Id of the "new place" hypothesis.
constexpr int kVirtualPlace = -1;

struct BayesFilterOptions {
  float virtualPlacePrior = 0.9f;  // Bayes/VirtualPlacePriorThr
  // Bayes/PredictionLC: [to virtual place, to self, to 1 link away, 2 links away, ...].
  std::vector<float> predictionLC = {0.1f, 0.36f, 0.30f, 0.16f, 0.062f, 0.0151f, 0.00255f,
                                     0.000324f, 2.5e-05f, 1.3e-06f, 4.8e-08f, 1.2e-09f,
                                     1.9e-11f, 2.2e-13f, 1.7e-15f, 8.5e-18f, 2.9e-20f, 6.9e-23f};
  bool fullPredictionUpdate = false;  // Bayes/FullPredictionUpdate

  static BayesFilterOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
  // Largest graph distance (links) a transition reaches: predictionLC.size() - 2.
  int maxNeighborDepth() const { return static_cast<int>(predictionLC.size()) - 2; }
};

// Graph neighbourhood of a location: id -> distance in links (0 = the location itself), over
// the locations within maxDepth links. Given by the memory (neighbour links of the graph).
using NeighborsFn = std::function<std::map<int, int>(int id, int maxDepth)>;

struct BayesFilterSummary {
  int hypotheses = 0;           // WM locations + the virtual place
  int predictionRowsUpdated = 0;
  double predictionMs = 0.0;    // transition model (rows) and prior
  double posteriorMs = 0.0;     // product with the likelihood and normalisation
};

class BayesFilter {
 public:
  explicit BayesFilter(const BayesFilterOptions& options = BayesFilterOptions());

  // One filter step. `likelihood` holds one adjusted value per hypothesis: kVirtualPlace and
  // every WM location that can close a loop now (the hypothesis set of this step). Returns the
  // posterior over the same keys, summing to 1. Throws std::invalid_argument if the virtual
  // place is missing or a value is negative or not finite.
  const std::map<int, float>& update(const std::map<int, float>& likelihood,
                                     const NeighborsFn& neighbors);
  // The same step on the flat form: `likelihood` sorted by id, kVirtualPlace first (throws
  // std::invalid_argument otherwise). Returns the posterior in the same form.
  const Scores& updateScores(const Scores& likelihood, const NeighborsFn& neighbors);

  // The prior of the last update (the prediction before the likelihood), for statistics.
  const std::map<int, float>& prior() const;
  const std::map<int, float>& posterior() const;
  const Scores& posteriorScores() const { return posterior_; }
  const BayesFilterSummary& summary() const { return summary_; }

  // The graph around these locations changed (a link was added or removed): their cached
  // transition rows and those of their neighbours are recomputed at the next update.
  void invalidateNeighborhood(const std::set<int>& ids, const NeighborsFn& neighbors);
  // Forget the posterior (e.g. a new map started): the next update starts from the virtual place.
  void reset();

  const BayesFilterOptions& options() const { return options_; }

 private:
  using Row = std::vector<std::pair<int, float>>;  // (to id, probability) without the virtual place
  const Row& transitionRow(int from, const IdPositions& hypotheses, const NeighborsFn& neighbors);
  void dropStaleRows(const std::vector<int>& hypotheses, const NeighborsFn& neighbors);
  Scores predict(const std::vector<int>& hypotheses, const NeighborsFn& neighbors);

  BayesFilterOptions options_;
  Scores posterior_;
  Scores prior_;
  std::vector<int> previousHypotheses_;  // the WM ids of the last update, sorted
  std::unordered_map<int, Row> rows_;   // cached transition rows, keyed by the "from" location
  BayesFilterSummary summary_;
  // The std::map views of prior_ and posterior_, built on demand (statistics, tests).
  mutable std::map<int, float> priorMap_, posteriorMap_;
  mutable bool priorMapValid_ = false, posteriorMapValid_ = false;
};

}  // namespace rtabmap::bayes

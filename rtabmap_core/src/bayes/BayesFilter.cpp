#include "rtabmap_core/bayes/BayesFilter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "rtabmap_core/common/Error.h"

namespace rtabmap::bayes {
namespace {

double elapsedMs(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

// The location ids of a sorted flat likelihood (after the virtual place).
std::vector<int> hypothesisIds(const Scores& likelihood) {
  std::vector<int> ids;
  ids.reserve(likelihood.size());
  for (const auto& [id, value] : likelihood) {
    (void)value;
    if (id != kVirtualPlace) ids.push_back(id);
  }
  return ids;
}

void checkLikelihood(const Scores& likelihood) {
  if (likelihood.empty() || likelihood.front().first != kVirtualPlace) {
    throw std::invalid_argument("BayesFilter::update: the likelihood has no virtual-place (new place) entry");
  }
  int previous = kVirtualPlace;
  for (size_t i = 0; i < likelihood.size(); ++i) {
    const auto& [id, value] = likelihood[i];
    if (i > 0 && id <= previous) {
      throw std::invalid_argument("BayesFilter::updateScores: the likelihood is not sorted by id (at " +
                                  std::to_string(id) + ")");
    }
    previous = id;
    if (!std::isfinite(value) || value < 0.0f) {
      std::ostringstream msg;
      msg << "BayesFilter::update: likelihood of location " << id << " is " << value
          << " (must be finite and >= 0)";
      throw std::invalid_argument(msg.str());
    }
  }
}

}  // namespace

BayesFilterOptions BayesFilterOptions::fromParameters(const ParametersMap& parameters) {
  BayesFilterOptions options;
  options.virtualPlacePrior = Parameters::getFloat(parameters, Parameters::kBayesVirtualPlacePriorThr());
  options.predictionLC.clear();
  for (double v : Parameters::getNumberList(parameters, Parameters::kBayesPredictionLC())) {
    options.predictionLC.push_back(static_cast<float>(v));
  }
  options.fullPredictionUpdate = Parameters::getBool(parameters, Parameters::kBayesFullPredictionUpdate());
  std::string why;
  if (!options.IsValid(&why)) throw ParameterError(why);
  return options;
}

bool BayesFilterOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& message) {
    if (why) *why = message;
    return false;
  };
  if (!(virtualPlacePrior >= 0.0f && virtualPlacePrior <= 1.0f)) {
    return fail(Parameters::kBayesVirtualPlacePriorThr() + " must be in [0, 1]");
  }
  if (predictionLC.size() < 2) {
    return fail(Parameters::kBayesPredictionLC() +
                " needs at least two values: the probability to go to the new place, then to "
                "stay on the same location");
  }
  for (float p : predictionLC) {
    if (!(p >= 0.0f && p <= 1.0f)) return fail(Parameters::kBayesPredictionLC() + " values must be in [0, 1]");
  }
  if (predictionLC[0] >= 1.0f) {
    return fail(Parameters::kBayesPredictionLC() + ": the first value (to the new place) must be under 1");
  }
  if (predictionLC[1] <= 0.0f) {
    return fail(Parameters::kBayesPredictionLC() + ": the second value (stay on the same location) must be positive");
  }
  return true;
}

BayesFilter::BayesFilter(const BayesFilterOptions& options) : options_(options) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("BayesFilter: " + why);
}

void BayesFilter::reset() {
  posterior_.clear();
  prior_.clear();
  previousHypotheses_.clear();
  rows_.clear();
  summary_ = BayesFilterSummary();
  priorMapValid_ = posteriorMapValid_ = false;
}

const std::map<int, float>& BayesFilter::prior() const {
  if (!priorMapValid_) priorMap_ = toMap(prior_);
  priorMapValid_ = true;
  return priorMap_;
}

const std::map<int, float>& BayesFilter::posterior() const {
  if (!posteriorMapValid_) posteriorMap_ = toMap(posterior_);
  posteriorMapValid_ = true;
  return posteriorMap_;
}

void BayesFilter::invalidateNeighborhood(const std::set<int>& ids, const NeighborsFn& neighbors) {
  if (rows_.empty()) return;  // nothing cached (first update, full updates): no graph walk
  for (int id : ids) {
    rows_.erase(id);
    if (!neighbors) continue;
    for (const auto& [near, depth] : neighbors(id, options_.maxNeighborDepth())) {
      (void)depth;
      rows_.erase(near);
    }
  }
}

// A row is stale when the hypothesis set changed within its reach: a location entered the set
// near it (found through the graph from the new location), or a location of the row left the
// set (found in the row itself: the departed location may not be in the graph any more).
void BayesFilter::dropStaleRows(const std::vector<int>& hypotheses, const NeighborsFn& neighbors) {
  std::vector<int> added, removed;
  std::set_difference(hypotheses.begin(), hypotheses.end(), previousHypotheses_.begin(), previousHypotheses_.end(),
                      std::back_inserter(added));
  std::set_difference(previousHypotheses_.begin(), previousHypotheses_.end(), hypotheses.begin(), hypotheses.end(),
                      std::back_inserter(removed));
  if (!removed.empty()) {
    const IdPositions gone(removed);
    for (int id : removed) rows_.erase(id);
    for (auto it = rows_.begin(); it != rows_.end();) {
      const bool stale = std::any_of(it->second.begin(), it->second.end(),
                                     [&gone](const std::pair<int, float>& entry) { return gone.contains(entry.first); });
      it = stale ? rows_.erase(it) : std::next(it);
    }
  }
  invalidateNeighborhood(std::set<int>(added.begin(), added.end()), neighbors);
}

const BayesFilter::Row& BayesFilter::transitionRow(int from, const IdPositions& hypotheses,
                                                   const NeighborsFn& neighbors) {
  auto cached = rows_.find(from);
  if (cached != rows_.end()) return cached->second;

  Row row;
  std::map<int, int> near = neighbors ? neighbors(from, options_.maxNeighborDepth()) : std::map<int, int>();
  near[from] = 0;  // the location itself, whatever the graph says
  double sum = 0.0;
  for (const auto& [id, depth] : near) {
    if (!hypotheses.contains(id) || depth < 0 || depth > options_.maxNeighborDepth()) continue;
    float p = options_.predictionLC[static_cast<size_t>(depth) + 1];
    if (p <= 0.0f) continue;
    row.emplace_back(id, p);
    sum += p;
  }
  // The loop-closure part of the row sums to 1 - p0 (the paper's "normalised to 0.9").
  const double scale = (1.0 - options_.predictionLC[0]) / sum;
  for (auto& entry : row) entry.second = static_cast<float>(entry.second * scale);
  ++summary_.predictionRowsUpdated;
  return rows_.emplace(from, std::move(row)).first->second;
}

// The prior over [virtual place, hypotheses...]: O(WM) for the virtual place's uniform spread,
// O(WM x neighbourhood) for the rows; every sum is made in the order of the map version (ids
// ascending), so the values are the same to the last bit.
Scores BayesFilter::predict(const std::vector<int>& hypotheses, const NeighborsFn& neighbors) {
  const IdPositions position(hypotheses);
  std::vector<double> prior(hypotheses.size() + 1, 0.0);  // [0]: the virtual place

  // Previous posterior; the first update starts from "new place" with certainty.
  const Scores start{{kVirtualPlace, 1.0f}};
  const Scores& previous = posterior_.empty() ? start : posterior_;

  const double pVirtual = previous.front().first == kVirtualPlace ? previous.front().second : 0.0;
  prior[0] += pVirtual * options_.virtualPlacePrior;
  if (!hypotheses.empty()) {
    const double spread = pVirtual * (1.0 - options_.virtualPlacePrior) / hypotheses.size();
    for (size_t i = 1; i < prior.size(); ++i) prior[i] += spread;
  }
  for (const auto& [from, p] : previous) {
    // Locations that left the hypothesis set (moved to LTM, merged, in STM again) take their
    // probability with them; the normalisation of the posterior accounts for it.
    if (from == kVirtualPlace || p <= 0.0f || !position.contains(from)) continue;
    prior[0] += p * options_.predictionLC[0];
    for (const auto& [to, t] : transitionRow(from, position, neighbors)) {
      const int k = position.find(to);  // always found: rows with a departed location were dropped
      if (k >= 0) prior[static_cast<size_t>(k) + 1] += p * t;
    }
  }
  Scores result;
  result.reserve(prior.size());
  result.emplace_back(kVirtualPlace, static_cast<float>(prior[0]));
  for (size_t i = 0; i < hypotheses.size(); ++i) result.emplace_back(hypotheses[i], static_cast<float>(prior[i + 1]));
  return result;
}

const std::map<int, float>& BayesFilter::update(const std::map<int, float>& likelihood,
                                                const NeighborsFn& neighbors) {
  if (!likelihood.count(kVirtualPlace)) {
    throw std::invalid_argument("BayesFilter::update: the likelihood has no virtual-place (new place) entry");
  }
  updateScores(toScores(likelihood), neighbors);
  return posterior();
}

const Scores& BayesFilter::updateScores(const Scores& likelihood, const NeighborsFn& neighbors) {
  checkLikelihood(likelihood);
  summary_ = BayesFilterSummary();
  summary_.hypotheses = static_cast<int>(likelihood.size());
  priorMapValid_ = posteriorMapValid_ = false;
  auto start = std::chrono::steady_clock::now();

  std::vector<int> hypotheses = hypothesisIds(likelihood);
  if (options_.fullPredictionUpdate) {
    rows_.clear();
  } else {
    dropStaleRows(hypotheses, neighbors);
  }
  prior_ = predict(hypotheses, neighbors);
  previousHypotheses_ = std::move(hypotheses);
  summary_.predictionMs = elapsedMs(start);

  start = std::chrono::steady_clock::now();
  // prior_ and the likelihood have the same ids in the same order.
  Scores posterior(likelihood.size());
  double sum = 0.0;
  for (size_t i = 0; i < likelihood.size(); ++i) {
    const double p = static_cast<double>(likelihood[i].second) * prior_[i].second;
    posterior[i] = {likelihood[i].first, static_cast<float>(p)};
    sum += p;
  }
  if (sum > 0.0) {
    for (auto& entry : posterior) entry.second = static_cast<float>(entry.second / sum);
  } else {
    // Every hypothesis has zero likelihood: nothing is known, the place is new.
    for (auto& entry : posterior) entry.second = entry.first == kVirtualPlace ? 1.0f : 0.0f;
  }
  posterior_ = std::move(posterior);
  summary_.posteriorMs = elapsedMs(start);
  return posterior_;
}

}  // namespace rtabmap::bayes

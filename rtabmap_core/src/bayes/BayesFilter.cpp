#include "rtabmap_core/bayes/BayesFilter.h"

#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "rtabmap_core/common/Error.h"

namespace rtabmap::bayes {
namespace {

double elapsedMs(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

std::set<int> keysWithoutVirtual(const std::map<int, float>& m) {
  std::set<int> keys;
  for (const auto& [id, value] : m) {
    if (id != kVirtualPlace) keys.insert(keys.end(), id);
  }
  return keys;
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
  rows_.clear();
  summary_ = BayesFilterSummary();
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
void BayesFilter::dropStaleRows(const std::set<int>& added, const std::set<int>& removed,
                                const NeighborsFn& neighbors) {
  for (int id : removed) rows_.erase(id);
  if (!removed.empty()) {
    for (auto it = rows_.begin(); it != rows_.end();) {
      bool stale = false;
      for (const auto& [to, p] : it->second) {
        (void)p;
        if (removed.count(to)) {
          stale = true;
          break;
        }
      }
      it = stale ? rows_.erase(it) : std::next(it);
    }
  }
  invalidateNeighborhood(added, neighbors);
}

const BayesFilter::Row& BayesFilter::transitionRow(int from, const std::set<int>& hypotheses,
                                                   const NeighborsFn& neighbors) {
  auto cached = rows_.find(from);
  if (cached != rows_.end()) return cached->second;

  Row row;
  std::map<int, int> near = neighbors ? neighbors(from, options_.maxNeighborDepth()) : std::map<int, int>();
  near[from] = 0;  // the location itself, whatever the graph says
  double sum = 0.0;
  for (const auto& [id, depth] : near) {
    if (!hypotheses.count(id) || depth < 0 || depth > options_.maxNeighborDepth()) continue;
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

std::map<int, float> BayesFilter::predict(const std::set<int>& hypotheses, const NeighborsFn& neighbors) {
  std::map<int, double> prior;
  prior[kVirtualPlace] = 0.0;
  for (int id : hypotheses) prior.emplace_hint(prior.end(), id, 0.0);

  // Previous posterior; the first update starts from "new place" with certainty.
  std::map<int, float> previous = posterior_;
  if (previous.empty()) previous[kVirtualPlace] = 1.0f;

  const double pVirtual = previous.count(kVirtualPlace) ? previous.at(kVirtualPlace) : 0.0;
  prior[kVirtualPlace] += pVirtual * options_.virtualPlacePrior;
  if (!hypotheses.empty()) {
    const double spread = pVirtual * (1.0 - options_.virtualPlacePrior) / hypotheses.size();
    for (int id : hypotheses) prior[id] += spread;
  }
  for (const auto& [from, p] : previous) {
    // Locations that left the hypothesis set (moved to LTM, merged, in STM again) take their
    // probability with them; the normalisation of the posterior accounts for it.
    if (from == kVirtualPlace || p <= 0.0f || !hypotheses.count(from)) continue;
    prior[kVirtualPlace] += p * options_.predictionLC[0];
    for (const auto& [to, t] : transitionRow(from, hypotheses, neighbors)) prior[to] += p * t;
  }
  std::map<int, float> result;
  for (const auto& [id, p] : prior) result.emplace_hint(result.end(), id, static_cast<float>(p));
  return result;
}

const std::map<int, float>& BayesFilter::update(const std::map<int, float>& likelihood,
                                                const NeighborsFn& neighbors) {
  if (!likelihood.count(kVirtualPlace)) {
    throw std::invalid_argument("BayesFilter::update: the likelihood has no virtual-place (new place) entry");
  }
  for (const auto& [id, value] : likelihood) {
    if (!std::isfinite(value) || value < 0.0f) {
      std::ostringstream msg;
      msg << "BayesFilter::update: likelihood of location " << id << " is " << value
          << " (must be finite and >= 0)";
      throw std::invalid_argument(msg.str());
    }
  }
  summary_ = BayesFilterSummary();
  summary_.hypotheses = static_cast<int>(likelihood.size());
  auto start = std::chrono::steady_clock::now();

  const std::set<int> hypotheses = keysWithoutVirtual(likelihood);
  if (options_.fullPredictionUpdate) {
    rows_.clear();
  } else {
    const std::set<int> previous = keysWithoutVirtual(prior_);
    std::set<int> added, removed;
    for (int id : hypotheses) if (!previous.count(id)) added.insert(id);
    for (int id : previous) if (!hypotheses.count(id)) removed.insert(id);
    dropStaleRows(added, removed, neighbors);
  }
  prior_ = predict(hypotheses, neighbors);
  summary_.predictionMs = elapsedMs(start);

  start = std::chrono::steady_clock::now();
  std::map<int, float> posterior;
  double sum = 0.0;
  for (const auto& [id, l] : likelihood) {
    const double p = static_cast<double>(l) * prior_.at(id);
    posterior.emplace_hint(posterior.end(), id, static_cast<float>(p));
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

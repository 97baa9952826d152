#include "rtabmap_core/bayes/Likelihood.h"

#include <cmath>
#include <sstream>

#include "rtabmap_core/bayes/BayesFilter.h"

namespace rtabmap::bayes {

std::map<int, float> adjustLikelihood(const std::map<int, float>& similarity) {
  return toMap(adjustLikelihoodScores(toScores(similarity)));
}

Scores adjustLikelihoodScores(const Scores& similarity) {
  double sum = 0.0, sumSq = 0.0;
  int n = 0;
  for (const auto& [id, s] : similarity) {
    if (id == kVirtualPlace || !(s > 0.0f)) continue;
    sum += s;
    sumSq += static_cast<double>(s) * s;
    ++n;
  }
  const double mean = n ? sum / n : 0.0;
  const double variance = n ? std::max(0.0, sumSq / n - mean * mean) : 0.0;
  const double stdDev = std::sqrt(variance);

  Scores likelihood;
  likelihood.reserve(similarity.size() + 1);
  likelihood.emplace_back(kVirtualPlace, 2.0f);  // set below
  bool someoneStandsOut = false;
  for (const auto& [id, s] : similarity) {
    if (id == kVirtualPlace) continue;
    float l = 1.0f;
    if (mean > 0.0 && s >= mean + stdDev && stdDev > 0.0) {
      // (s - sigma) / mu >= 1 whenever s >= mu + sigma; the max only guards rounding.
      l = std::max(1.0f, static_cast<float>((s - stdDev) / mean));
      someoneStandsOut = true;
    }
    likelihood.emplace_back(id, l);
  }
  // Without a location standing out there is no evidence of a loop: the new place gets twice
  // the likelihood of any location (the original's value), which keeps the posterior of a flat
  // likelihood from drifting to the locations: its fixed point is p(new) = 0.90, so the
  // loop-closure probability stays at 0.098, under the default Rtabmap/LoopThr of 0.11.
  likelihood.front().second = someoneStandsOut ? std::max(1.0f, static_cast<float>(mean / stdDev + 1.0)) : 2.0f;
  return likelihood;
}

HypothesisOptions HypothesisOptions::fromParameters(const ParametersMap& parameters) {
  HypothesisOptions options;
  options.loopThr = Parameters::getFloat(parameters, Parameters::kRtabmapLoopThr());
  options.loopRatio = Parameters::getFloat(parameters, Parameters::kRtabmapLoopRatio());
  return options;
}

bool HypothesisOptions::IsValid(std::string* why) const {
  if (!(loopThr >= 0.0f && loopThr <= 1.0f) || !(loopRatio >= 0.0f && loopRatio <= 1.0f)) {
    if (why) *why = Parameters::kRtabmapLoopThr() + " and " + Parameters::kRtabmapLoopRatio() + " must be in [0, 1]";
    return false;
  }
  return true;
}

Hypothesis selectHypothesis(const std::map<int, float>& posterior, const HypothesisOptions& options,
                            float previousValue) {
  return selectHypothesisScores(toScores(posterior), options, previousValue);
}

Hypothesis selectHypothesisScores(const Scores& posterior, const HypothesisOptions& options, float previousValue) {
  Hypothesis h;
  for (const auto& [id, p] : posterior) {
    // Ties go to the most recent location (largest id), like the original's reverse scan.
    if (id > 0 && p > 0.0f && p >= h.locationValue) {
      h.id = id;
      h.locationValue = p;
    }
  }
  if (h.id == 0) return h;
  const bool hasVirtual = !posterior.empty() && posterior.front().first == kVirtualPlace;
  h.value = hasVirtual ? 1.0f - posterior.front().second : 1.0f;
  std::ostringstream why;
  if (posterior.size() <= 2) {
    // One candidate only: it takes all the loop-closure mass whatever it looks like.
    why << "single hypothesis";
  } else if (h.value < options.loopThr) {
    why << "loop-closure probability " << h.value << " < Rtabmap/LoopThr " << options.loopThr;
  } else if (options.loopRatio > 0.0f && h.value < options.loopRatio * previousValue) {
    why << "loop-closure probability " << h.value << " < Rtabmap/LoopRatio " << options.loopRatio
        << " x previous " << previousValue;
  } else {
    h.accepted = true;
  }
  h.rejectedBecause = why.str();
  return h;
}

}  // namespace rtabmap::bayes

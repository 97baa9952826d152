#pragma once
// From raw similarities to the likelihood of the Bayes filter (T-RO 2013, eq. 3-4), and the
// selection of the loop-closure hypothesis from the posterior (section III-E).
#include <map>
#include <string>

#include "rtabmap_core/bayes/Scores.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap::bayes {

// Eq. 3-4. `similarity` holds a raw score s_i >= 0 per Working-Memory location (TF-IDF or eq. 1).
// mu and sigma are the mean and standard deviation of the non-zero scores (locations sharing no
// word with the new one say nothing about the distribution). Then
//   l(i) = (s_i - sigma) / mu   if s_i >= mu + sigma,   else 1;
//   l(virtual place) = mu / sigma + 1 when some location stands out (s_i >= mu + sigma,
//   sigma > 0), else 2: no evidence of a loop (see Likelihood.cpp for why 2).
// The result has every key of `similarity` plus kVirtualPlace.
std::map<int, float> adjustLikelihood(const std::map<int, float>& similarity);
// The same on the flat form (sorted by id): the result has kVirtualPlace first.
Scores adjustLikelihoodScores(const Scores& similarity);

struct HypothesisOptions {
  float loopThr = 0.11f;   // Rtabmap/LoopThr
  float loopRatio = 0.0f;  // Rtabmap/LoopRatio
  static HypothesisOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
};

struct Hypothesis {
  int id = 0;                 // highest WM location, 0 if none
  float value = 0.0f;         // loop-closure probability: 1 - p(new place)
  float locationValue = 0.0f; // posterior of that location alone
  bool accepted = false;
  std::string rejectedBecause;  // empty when accepted or when no location was a candidate
};

// The location of highest posterior is the candidate; the hypothesis value is the total
// loop-closure probability, 1 - p(new place), as the original implementation does (the mass of a
// revisited place is spread over the neighbouring locations by the transition model, so the
// candidate alone understates it). Accepted when value >= loopThr and, if loopRatio > 0, when
// value >= loopRatio * previousValue (the value of the previous update). A posterior with a
// single location (besides the new place) is never accepted: that location takes all the
// loop-closure mass whatever it looks like.
Hypothesis selectHypothesis(const std::map<int, float>& posterior, const HypothesisOptions& options,
                            float previousValue);
// The same on the flat form (sorted by id).
Hypothesis selectHypothesisScores(const Scores& posterior, const HypothesisOptions& options, float previousValue);

}  // namespace rtabmap::bayes

#include "rtabmap_core/vocabulary/Similarity.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "rtabmap_core/bayes/Scores.h"

namespace rtabmap::vocabulary {

std::map<int, int> wordCounts(const std::multimap<int, int>& words) {
  std::map<int, int> counts;
  for (const auto& [wordId, keypoint] : words) {
    (void)keypoint;
    if (wordId > 0) ++counts[wordId];  // id 0: a keypoint that was not quantised
  }
  return counts;
}

namespace {
int total(const std::map<int, int>& counts) {
  int n = 0;
  for (const auto& [id, c] : counts) n += c;
  return n;
}
}  // namespace

float similarity(const std::multimap<int, int>& wordsA, const std::multimap<int, int>& wordsB) {
  const auto a = wordCounts(wordsA), b = wordCounts(wordsB);
  const int na = total(a), nb = total(b);
  if (na == 0 || nb == 0) return 0.0f;
  int pairs = 0;
  auto ia = a.begin();
  auto ib = b.begin();
  while (ia != a.end() && ib != b.end()) {
    if (ia->first < ib->first) {
      ++ia;
    } else if (ib->first < ia->first) {
      ++ib;
    } else {
      pairs += std::min(ia->second, ib->second);
      ++ia;
      ++ib;
    }
  }
  return static_cast<float>(pairs) / static_cast<float>(std::max(na, nb));
}

std::map<int, float> computeLikelihood(const Vocabulary& vocabulary, const std::multimap<int, int>& newWords,
                                       const std::unordered_map<int, int>& candidates, int totalLocations,
                                       bool tfIdf) {
  std::vector<std::pair<int, int>> sorted(candidates.begin(), candidates.end());
  std::sort(sorted.begin(), sorted.end());
  const auto scores = computeLikelihoodScores(vocabulary, newWords, sorted, totalLocations, tfIdf);
  return std::map<int, float>(scores.begin(), scores.end());
}

std::vector<std::pair<int, float>> computeLikelihoodScores(const Vocabulary& vocabulary,
                                                           const std::multimap<int, int>& newWords,
                                                           const std::vector<std::pair<int, int>>& candidates,
                                                           int totalLocations, bool tfIdf) {
  // Scores accumulate in a flat array over the candidates, found by id in constant time; the
  // cost is the references of the new location's words, plus one pass over the candidates.
  std::vector<int> ids(candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i) ids[i] = candidates[i].first;
  const bayes::IdPositions position(ids);
  std::vector<double> score(candidates.size(), 0.0);
  const auto counts = wordCounts(newWords);
  const int newTotal = total(counts);
  for (const auto& [wordId, newCount] : counts) {
    const VisualWord* w = vocabulary.word(wordId);
    if (!w || w->references.empty()) continue;
    const double idf = tfIdf ? std::log10(static_cast<double>(std::max<int>(totalLocations, 1)) /
                                          static_cast<double>(w->references.size()))
                             : 0.0;
    for (const auto& [location, count] : w->references) {
      const int k = position.find(location);
      if (k < 0) continue;
      const int words = candidates[static_cast<size_t>(k)].second;
      if (words <= 0) continue;
      if (tfIdf) {
        score[static_cast<size_t>(k)] += (static_cast<double>(count) / words) * idf;
      } else {
        score[static_cast<size_t>(k)] += std::min(count, newCount);  // pairs; divided below
      }
    }
  }
  std::vector<std::pair<int, float>> likelihood(candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i) {
    double v = score[i];
    if (!tfIdf && v > 0.0) v /= std::max(newTotal, candidates[i].second);
    likelihood[i] = {candidates[i].first, static_cast<float>(std::max(0.0, v))};
  }
  return likelihood;
}

}  // namespace rtabmap::vocabulary

#include "rtabmap_core/vocabulary/Similarity.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

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
  // Scores accumulate in a table reserved for every candidate (no rehash however many share a
  // word); the cost is the references of the new location's words.
  std::unordered_map<int, double> score;
  score.reserve(candidates.size());
  const auto counts = wordCounts(newWords);
  const int newTotal = total(counts);
  for (const auto& [wordId, newCount] : counts) {
    const VisualWord* w = vocabulary.word(wordId);
    if (!w || w->references.empty()) continue;
    const double idf = tfIdf ? std::log10(static_cast<double>(std::max<int>(totalLocations, 1)) /
                                          static_cast<double>(w->references.size()))
                             : 0.0;
    for (const auto& [location, count] : w->references) {
      auto c = candidates.find(location);
      if (c == candidates.end() || c->second <= 0) continue;
      if (tfIdf) {
        score[location] += (static_cast<double>(count) / c->second) * idf;
      } else {
        score[location] += std::min(count, newCount);  // pairs; divided below
      }
    }
  }
  // Every candidate gets a value: sorted ids make each insertion into the map constant time.
  std::vector<std::pair<int, int>> sorted(candidates.begin(), candidates.end());
  std::sort(sorted.begin(), sorted.end());
  std::map<int, float> likelihood;
  for (const auto& [location, n] : sorted) {
    auto s = score.find(location);
    double v = s == score.end() ? 0.0 : s->second;
    if (!tfIdf && v > 0.0) v /= std::max(newTotal, n);
    likelihood.emplace_hint(likelihood.end(), location, static_cast<float>(std::max(0.0, v)));
  }
  return likelihood;
}

}  // namespace rtabmap::vocabulary

#pragma once
// The flat form of per-location values along the loop-closure pipeline (raw likelihood, adjusted
// likelihood, prior, posterior): (location id, value) pairs sorted by id, the new-place
// hypothesis (kVirtualPlace = -1) first when present.
//
// Why not std::map: with 20,000 locations in Working Memory every update builds and walks
// several of these; a sorted vector costs one allocation and sequential reads where a map costs
// one node per location and a cache miss per step, and lookups by id go through IdPositions.
#include <algorithm>
#include <map>
#include <utility>
#include <vector>

namespace rtabmap::bayes {

using Scores = std::vector<std::pair<int, float>>;

inline Scores toScores(const std::map<int, float>& m) { return Scores(m.begin(), m.end()); }

inline std::map<int, float> toMap(const Scores& s) {
  std::map<int, float> m;
  for (const auto& entry : s) m.emplace_hint(m.end(), entry);
  return m;
}

// Position of an id in a sorted list of distinct ids, in constant time: a table over the id
// range when the ids are dense enough (Working Memory ids mostly are), else binary search (a
// small WM of a long multi-session map, whose ids span millions).
class IdPositions {
 public:
  IdPositions() = default;
  explicit IdPositions(const std::vector<int>& sortedIds) : ids_(&sortedIds) {
    if (sortedIds.empty()) return;
    first_ = sortedIds.front();
    const long range = static_cast<long>(sortedIds.back()) - first_ + 1;
    if (range > 8 * static_cast<long>(sortedIds.size()) + 65536) return;
    table_.assign(static_cast<size_t>(range), -1);
    for (size_t i = 0; i < sortedIds.size(); ++i) table_[static_cast<size_t>(sortedIds[i] - first_)] = static_cast<int>(i);
  }

  // Index of `id` in the list, -1 if absent.
  int find(int id) const {
    if (!ids_ || ids_->empty()) return -1;
    if (!table_.empty()) {
      const long k = static_cast<long>(id) - first_;
      return k < 0 || k >= static_cast<long>(table_.size()) ? -1 : table_[static_cast<size_t>(k)];
    }
    auto it = std::lower_bound(ids_->begin(), ids_->end(), id);
    return it != ids_->end() && *it == id ? static_cast<int>(it - ids_->begin()) : -1;
  }
  bool contains(int id) const { return find(id) >= 0; }

 private:
  const std::vector<int>* ids_ = nullptr;  // not owned: lives as long as the caller's list
  int first_ = 0;
  std::vector<int> table_;
};

}  // namespace rtabmap::bayes

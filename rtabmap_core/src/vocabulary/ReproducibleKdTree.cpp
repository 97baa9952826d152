#include "ReproducibleKdTree.h"

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

namespace {

// Seeded at the start of every build; the build runs on one thread (the caller's).
thread_local std::mt19937 buildEngine;
constexpr unsigned kBuildSeed = 20130611u;  // any constant: only its being fixed matters

// Index of one of the `candidates` largest values of v[0..size), drawn uniformly.
template <class T>
int drawAmongLargest(const T* v, size_t size, int candidates) {
  constexpr int kMaxCandidates = 16;
  candidates = std::max(1, std::min(candidates, kMaxCandidates));
  int top[kMaxCandidates];  // dimensions, largest value first; ties keep the lower dimension
  int count = 0;
  for (int d = 0; d < static_cast<int>(size); ++d) {
    if (count == candidates && !(v[d] > v[top[count - 1]])) continue;
    int slot = count < candidates ? count++ : count - 1;
    for (; slot > 0 && v[d] > v[top[slot - 1]]; --slot) top[slot] = top[slot - 1];
    top[slot] = d;
  }
  std::uniform_int_distribution<int> pick(0, count - 1);
  return top[pick(buildEngine)];
}

}  // namespace

namespace flann {

#define RTABMAP_REPRODUCIBLE_KDTREE(DISTANCE)                                              \
  template <>                                                                              \
  void KDTreeIndex<DISTANCE>::buildIndexImpl() {                                           \
    std::vector<int> order(size_);                                                         \
    std::iota(order.begin(), order.end(), 0);                                              \
    mean_ = new DistanceType[veclen_];                                                     \
    var_ = new DistanceType[veclen_];                                                      \
    buildEngine.seed(kBuildSeed);                                                          \
    tree_roots_.resize(trees_);                                                            \
    for (auto& root : tree_roots_) {                                                       \
      std::shuffle(order.begin(), order.end(), buildEngine);                               \
      root = divideTree(order.data(), static_cast<int>(size_));                            \
    }                                                                                      \
    delete[] mean_;                                                                        \
    delete[] var_;                                                                         \
    mean_ = nullptr;                                                                       \
    var_ = nullptr;                                                                        \
  }                                                                                        \
  template <>                                                                              \
  int KDTreeIndex<DISTANCE>::selectDivision(DistanceType* variances) {                     \
    return drawAmongLargest(variances, veclen_, RAND_DIM);                                 \
  }

RTABMAP_REPRODUCIBLE_KDTREE(rtabmap::vocabulary::ReproducibleL2Bytes)
RTABMAP_REPRODUCIBLE_KDTREE(rtabmap::vocabulary::ReproducibleL2Floats)

#undef RTABMAP_REPRODUCIBLE_KDTREE

}  // namespace flann

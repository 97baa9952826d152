#include "rtabmap_core/bayes/Scores.h"

#include <gtest/gtest.h>

#include <random>

namespace rtabmap::bayes {
namespace {

// Both lookups (table over a dense id range, binary search over a sparse one) find every id at
// its position and nothing else.
void expectPositions(const std::vector<int>& ids, const std::vector<int>& absent) {
  const IdPositions positions(ids);
  for (size_t i = 0; i < ids.size(); ++i) EXPECT_EQ(positions.find(ids[i]), static_cast<int>(i)) << ids[i];
  for (int id : absent) EXPECT_EQ(positions.find(id), -1) << id;
}

TEST(IdPositions, DenseIds) {
  std::vector<int> ids;
  for (int id = 5; id < 2000; id += 3) ids.push_back(id);
  expectPositions(ids, {-1, 0, 4, 6, 7, 1999, 2000, 2001, 1 << 30});
}

TEST(IdPositions, SparseIdsSpanningMillions) {
  // A few WM locations of a long multi-session map: no table of millions of entries.
  const std::vector<int> ids{3, 17, 250000, 1000000, 40000000};
  expectPositions(ids, {-1, 0, 4, 16, 18, 249999, 1000001, 40000001});
}

TEST(IdPositions, EmptyAndDefault) {
  const std::vector<int> none;
  EXPECT_EQ(IdPositions(none).find(1), -1);
  EXPECT_EQ(IdPositions().find(1), -1);
}

TEST(Scores, MapRoundTripKeepsOrderAndValues) {
  const std::map<int, float> m{{-1, 0.5f}, {2, 0.25f}, {9, 0.125f}};
  const Scores s = toScores(m);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s.front().first, -1);
  EXPECT_EQ(toMap(s), m);
}

}  // namespace
}  // namespace rtabmap::bayes

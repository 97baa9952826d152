#include "rtabmap_core/vocabulary/Similarity.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <cmath>

namespace rtabmap::vocabulary {
namespace {

std::multimap<int, int> bag(std::initializer_list<int> wordIds) {
  std::multimap<int, int> words;
  int k = 0;
  for (int id : wordIds) words.emplace(id, k++);
  return words;
}

TEST(Similarity, EquationOneByHand) {
  // A: 1 1 2 3 (4 words), B: 1 2 2 4 5 (5 words): pairs min(2,1) + min(1,2) = 2.
  EXPECT_FLOAT_EQ(similarity(bag({1, 1, 2, 3}), bag({1, 2, 2, 4, 5})), 2.f / 5.f);
  EXPECT_FLOAT_EQ(similarity(bag({1, 2}), bag({1, 2})), 1.f);
  EXPECT_FLOAT_EQ(similarity(bag({}), bag({1})), 0.f);
}

// Three locations with hand-made words, referenced in a vocabulary: 1 = {1,1,2}, 2 = {2,3},
// 3 = {4}. New location {1,2}.
struct Fixture {
  Vocabulary v;
  // a, b, c: the ids of locations 1, 2, 3.
  explicit Fixture(int a = 1, int b = 2, int c = 3) {
    cv::Mat d = cv::Mat::eye(4, 4, CV_32F);  // equidistant: no ratio test passes, 4 words
    v.quantize(d, 99);  // words 1..4 referenced by location 99
    EXPECT_EQ(v.size(), 4u);
    std::multimap<int, int> all{{1, 0}, {2, 1}, {3, 2}, {4, 3}};
    v.removeReferences(99, all);
    v.addReference(1, a, 2);
    v.addReference(2, a, 1);
    v.addReference(2, b, 1);
    v.addReference(3, b, 1);
    v.addReference(4, c, 1);
  }
};

TEST(Similarity, TfIdfLikelihoodByHand) {
  Fixture f;
  std::unordered_map<int, int> candidates{{1, 3}, {2, 2}, {3, 1}};
  auto l = computeLikelihood(f.v, bag({1, 2}), candidates, 3, true);
  // Word 1: in 1 location (n_w = 1) -> idf log10(3); word 2: in 2 locations -> log10(1.5).
  EXPECT_NEAR(l.at(1), (2.0 / 3) * std::log10(3.0) + (1.0 / 3) * std::log10(1.5), 1e-6);
  EXPECT_NEAR(l.at(2), (1.0 / 2) * std::log10(1.5), 1e-6);
  EXPECT_FLOAT_EQ(l.at(3), 0.f);
}

TEST(Similarity, PairLikelihoodMatchesEquationOne) {
  Fixture f;
  std::unordered_map<int, int> candidates{{1, 3}, {2, 2}};
  auto l = computeLikelihood(f.v, bag({1, 2}), candidates, 3, false);
  EXPECT_FLOAT_EQ(l.at(1), similarity(bag({1, 2}), bag({1, 1, 2})));  // 2 / 3
  EXPECT_FLOAT_EQ(l.at(2), similarity(bag({1, 2}), bag({2, 3})));     // 1 / 2
  EXPECT_EQ(l.count(3), 0u);  // not a candidate
}

// The flat form: one score per candidate in the candidates' order; location ids spread over
// millions (a sparse WM, looked up by binary search) score as the compact ones do.
TEST(Similarity, FlatLikelihoodWithSparseIds) {
  Fixture compact, sparse(10, 2000000, 90000000);
  const auto expected = computeLikelihoodScores(compact.v, bag({1, 2}), {{1, 3}, {2, 2}, {3, 1}}, 3, true);
  const std::vector<std::pair<int, int>> candidates{{10, 3}, {2000000, 2}, {90000000, 1}};
  const auto scores = computeLikelihoodScores(sparse.v, bag({1, 2}), candidates, 3, true);
  ASSERT_EQ(expected.size(), 3u);
  ASSERT_EQ(scores.size(), 3u);
  for (size_t i = 0; i < scores.size(); ++i) {
    EXPECT_EQ(scores[i].first, candidates[i].first);
    EXPECT_EQ(scores[i].second, expected[i].second);
  }
  EXPECT_NEAR(scores[0].second, (2.0 / 3) * std::log10(3.0) + (1.0 / 3) * std::log10(1.5), 1e-6);
}

}  // namespace
}  // namespace rtabmap::vocabulary

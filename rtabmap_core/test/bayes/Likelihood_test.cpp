#include "rtabmap_core/bayes/Likelihood.h"

#include <gtest/gtest.h>

#include <cmath>

#include "rtabmap_core/bayes/BayesFilter.h"

namespace rtabmap::bayes {
namespace {

TEST(AdjustLikelihood, MatchesEquationFourByHand) {
  // Non-zero scores 1, 2, 3, 10: mean 4, variance (9 + 4 + 1 + 36) / 4 = 12.5.
  auto l = adjustLikelihood({{1, 0.f}, {2, 1.f}, {3, 2.f}, {4, 3.f}, {5, 10.f}});
  const double sigma = std::sqrt(12.5);
  EXPECT_NEAR(l.at(kVirtualPlace), 4.0 / sigma + 1.0, 1e-5);
  EXPECT_NEAR(l.at(5), (10.0 - sigma) / 4.0, 1e-5);  // over mean + sigma = 7.54
  for (int id : {1, 2, 3, 4}) EXPECT_FLOAT_EQ(l.at(id), 1.f);
  EXPECT_EQ(l.size(), 6u);
}

TEST(AdjustLikelihood, NoInformationGivesFlatLikelihood) {
  auto l = adjustLikelihood({{1, 0.f}, {2, 0.f}});
  EXPECT_FLOAT_EQ(l.at(kVirtualPlace), 2.f);
  EXPECT_FLOAT_EQ(l.at(1), 1.f);
  auto same = adjustLikelihood({{1, 2.f}, {2, 2.f}});  // sigma = 0: nobody stands out
  EXPECT_FLOAT_EQ(same.at(kVirtualPlace), 2.f);
  EXPECT_FLOAT_EQ(same.at(1), 1.f);
  EXPECT_EQ(adjustLikelihood({}).size(), 1u);
}

TEST(AdjustLikelihood, FlatLikelihoodNeverReachesTheLoopThreshold) {
  // Many updates without evidence: the loop-closure probability settles at 0.098 < 0.11.
  BayesFilter filter;
  std::map<int, float> raw;
  float loop = 0.f;
  for (int t = 1; t <= 200; ++t) {
    raw[t] = 0.f;
    std::map<int, float> l = adjustLikelihood(raw);
    const auto& post = filter.update(l, [](int id, int) { return std::map<int, int>{{id, 0}}; });
    loop = 1.f - post.at(kVirtualPlace);
    EXPECT_LT(loop, HypothesisOptions().loopThr) << "update " << t;
  }
  EXPECT_NEAR(loop, 0.098, 0.002);
}

TEST(SelectHypothesis, ValueIsTheLoopClosureMass) {
  HypothesisOptions o;
  std::map<int, float> post{{kVirtualPlace, 0.5f}, {1, 0.1f}, {2, 0.3f}, {3, 0.1f}};
  auto h = selectHypothesis(post, o, 0.f);
  EXPECT_EQ(h.id, 2);
  EXPECT_FLOAT_EQ(h.value, 0.5f);
  EXPECT_FLOAT_EQ(h.locationValue, 0.3f);
  EXPECT_TRUE(h.accepted);

  o.loopThr = 0.6f;
  h = selectHypothesis(post, o, 0.f);
  EXPECT_FALSE(h.accepted);
  EXPECT_NE(h.rejectedBecause.find("LoopThr"), std::string::npos);

  o.loopThr = 0.11f;
  o.loopRatio = 0.9f;
  EXPECT_FALSE(selectHypothesis(post, o, 0.6f).accepted);  // 0.5 < 0.9 * 0.6
  EXPECT_TRUE(selectHypothesis(post, o, 0.5f).accepted);
}

TEST(SelectHypothesis, SingleCandidateAndNoCandidate) {
  HypothesisOptions o;
  auto single = selectHypothesis({{kVirtualPlace, 0.1f}, {4, 0.9f}}, o, 0.f);
  EXPECT_EQ(single.id, 4);
  EXPECT_FALSE(single.accepted);
  auto none = selectHypothesis({{kVirtualPlace, 1.f}}, o, 0.f);
  EXPECT_EQ(none.id, 0);
  EXPECT_FALSE(none.accepted);
}

TEST(SelectHypothesis, TieGoesToTheNewestLocation) {
  auto h = selectHypothesis({{kVirtualPlace, 0.4f}, {1, 0.3f}, {7, 0.3f}}, HypothesisOptions(), 0.f);
  EXPECT_EQ(h.id, 7);
}

}  // namespace
}  // namespace rtabmap::bayes

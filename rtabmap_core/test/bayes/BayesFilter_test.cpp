#include "rtabmap_core/bayes/BayesFilter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "common/TestData.h"

namespace rtabmap::bayes {
namespace {

// A graph given by undirected edges; neighbours by breadth-first search.
struct Graph {
  std::multimap<int, int> edges;
  void link(int a, int b) {
    edges.emplace(a, b);
    edges.emplace(b, a);
  }
  std::map<int, int> neighbors(int id, int maxDepth) const {
    std::map<int, int> depth{{id, 0}};
    std::vector<int> frontier{id};
    for (int d = 1; d <= maxDepth && !frontier.empty(); ++d) {
      std::vector<int> next;
      for (int n : frontier) {
        auto [b, e] = edges.equal_range(n);
        for (auto it = b; it != e; ++it) {
          if (depth.emplace(it->second, d).second) next.push_back(it->second);
        }
      }
      frontier.swap(next);
    }
    return depth;
  }
  NeighborsFn fn() const {
    return [this](int id, int maxDepth) { return neighbors(id, maxDepth); };
  }
};

Graph chain(int first, int last) {
  Graph g;
  for (int i = first; i < last; ++i) g.link(i, i + 1);
  return g;
}

BayesFilterOptions shortModel() {
  BayesFilterOptions o;
  o.predictionLC = {0.1f, 0.5f, 0.25f};  // virtual, self, one link away
  return o;
}

TEST(BayesFilter, FirstUpdateStartsFromTheNewPlace) {
  Graph g = chain(1, 3);
  BayesFilter filter(shortModel());
  const auto& post = filter.update({{kVirtualPlace, 1.f}, {1, 1.f}, {2, 1.f}, {3, 1.f}}, g.fn());
  // Virtual -> virtual 0.9, virtual -> each of the 3 locations 0.1 / 3; flat likelihood.
  EXPECT_NEAR(filter.prior().at(kVirtualPlace), 0.9, 1e-6);
  for (int id : {1, 2, 3}) EXPECT_NEAR(filter.prior().at(id), 0.1 / 3, 1e-6);
  EXPECT_NEAR(post.at(kVirtualPlace), 0.9, 1e-6);
  EXPECT_NEAR(post.at(2), 0.1 / 3, 1e-6);
}

TEST(BayesFilter, TransitionFromLocationsMatchesHandComputation) {
  Graph g = chain(1, 3);
  BayesFilter filter(shortModel());
  filter.update({{kVirtualPlace, 1.f}, {1, 1.f}, {2, 10.f}, {3, 1.f}}, g.fn());
  // posterior after step 1: (0.9, 1/30, 10/30, 1/30) / 1.3
  const double v = 0.9 / 1.3, p1 = (1.0 / 30) / 1.3, p2 = (10.0 / 30) / 1.3, p3 = p1;
  EXPECT_NEAR(filter.posterior().at(2), p2, 1e-6);

  filter.update({{kVirtualPlace, 1.f}, {1, 1.f}, {2, 1.f}, {3, 1.f}}, g.fn());
  // Rows (self 0.5, one link 0.25, normalised to 0.9): from 1 (ends of the chain): 1->1 0.6,
  // 1->2 0.3; from 2: 2->2 0.45, 2->1 0.225, 2->3 0.225; from 3 like from 1.
  const double spread = v * 0.1 / 3;
  const auto& prior = filter.prior();
  EXPECT_NEAR(prior.at(kVirtualPlace), v * 0.9 + (p1 + p2 + p3) * 0.1, 1e-6);
  EXPECT_NEAR(prior.at(1), spread + p1 * 0.6 + p2 * 0.225, 1e-6);
  EXPECT_NEAR(prior.at(2), spread + p1 * 0.3 + p2 * 0.45 + p3 * 0.3, 1e-6);
  EXPECT_NEAR(prior.at(3), spread + p2 * 0.225 + p3 * 0.6, 1e-6);
  double sum = 0;
  for (const auto& [id, p] : prior) sum += p;
  EXPECT_NEAR(sum, 1.0, 1e-6);  // nothing left the hypothesis set: probability is conserved
}

TEST(BayesFilter, NeighboursOutsideTheHypothesesDropOutOfTheRow) {
  Graph g = chain(1, 3);  // 3 is in the graph but not a hypothesis (still in STM)
  BayesFilter filter(shortModel());
  filter.update({{kVirtualPlace, 1.f}, {1, 1.f}, {2, 8.f}}, g.fn());
  const double v = 0.9 / (0.9 + 0.05 + 0.4), p1 = 0.05 / 1.35, p2 = 0.4 / 1.35;
  filter.update({{kVirtualPlace, 1.f}, {1, 1.f}, {2, 1.f}}, g.fn());
  // From 2: self 0.5 and 1 at 0.25 -> normalised to 0.9: 0.6 and 0.3.
  EXPECT_NEAR(filter.prior().at(2), v * 0.05 + p1 * 0.3 + p2 * 0.6, 1e-6);
  EXPECT_NEAR(filter.prior().at(1), v * 0.05 + p1 * 0.6 + p2 * 0.3, 1e-6);
}

TEST(BayesFilter, TransitionsReachAsFarAsTheModelIsLong) {
  // 18 values = virtual, self and 16 link depths (the default's length), all equal so the
  // reach is visible: from 20 the mass spreads evenly over 4..36 (33 locations).
  Graph g = chain(1, 40);
  BayesFilterOptions o;
  o.predictionLC.assign(18, 0.05f);
  o.predictionLC[0] = 0.1f;
  EXPECT_EQ(o.maxNeighborDepth(), 16);
  BayesFilter filter(o);
  std::map<int, float> l{{kVirtualPlace, 1.f}};
  for (int i = 1; i <= 40; ++i) l[i] = i == 20 ? 1000.f : 1.f;
  filter.update(l, g.fn());
  const double p20 = filter.posterior().at(20);
  for (auto& e : l) e.second = 1.f;
  filter.update(l, g.fn());
  // prior(4) sums the rows of 1..20, prior(3) those of 1..19: the difference is 20's share,
  // so 20 reaches 4 (16 links) and not 3 (17 links); same on the other side.
  EXPECT_NEAR(filter.prior().at(4) - filter.prior().at(3), p20 * 0.9 / 33, 1e-5);
  EXPECT_NEAR(filter.prior().at(36) - filter.prior().at(37), p20 * 0.9 / 33, 1e-5);
  EXPECT_GT(p20, 0.5);
}

TEST(BayesFilter, DefaultModelIsSymmetricAndPeaksOnTheLocation) {
  Graph g = chain(1, 40);
  BayesFilter filter;
  std::map<int, float> l{{kVirtualPlace, 1.f}};
  for (int i = 1; i <= 40; ++i) l[i] = i == 20 ? 1000.f : 1.f;
  filter.update(l, g.fn());
  for (auto& e : l) e.second = 1.f;
  filter.update(l, g.fn());
  EXPECT_NEAR(filter.prior().at(19), filter.prior().at(21), 1e-6);
  EXPECT_GT(filter.prior().at(20), filter.prior().at(19));
  EXPECT_GT(filter.prior().at(19), filter.prior().at(18));
  double sum = 0;
  for (const auto& [id, p] : filter.prior()) sum += p;
  EXPECT_NEAR(sum, 1.0, 1e-5);
}

TEST(BayesFilter, CachedRowsGiveTheSameResultAsFullUpdates) {
  std::mt19937 rng(test::drawSeed(7));
  Graph g;
  // Flat weights over 16 links: every depth matters at the test's tolerance.
  BayesFilterOptions cachedOptions;
  cachedOptions.predictionLC.assign(18, 0.05f);
  cachedOptions.predictionLC[0] = 0.1f;
  BayesFilterOptions fullOptions = cachedOptions;
  fullOptions.fullPredictionUpdate = true;
  BayesFilter cached(cachedOptions), full(fullOptions);
  std::set<int> wm;
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (int t = 1; t <= 120; ++t) {
    if (t > 1) g.link(t - 1, t);
    wm.insert(t);
    // Transfer: drop a random old location now and then; retrieval: bring one back.
    if (t > 20 && u(rng) < 0.3f) wm.erase(std::next(wm.begin(), static_cast<long>(u(rng) * (wm.size() - 5))));
    if (t > 30 && u(rng) < 0.2f) wm.insert(1 + static_cast<int>(u(rng) * (t - 1)));
    // A loop-closure link changes the neighbourhood: the cached filter is told.
    if (t > 40 && t % 17 == 0) {
      // Between two older locations, out of reach of the new one (whose neighbourhood is walked
      // anyway), so only the notification refreshes the rows around them.
      int other = 1 + static_cast<int>(u(rng) * (t - 30));
      g.link(t - 20, other);
      cached.invalidateNeighborhood({t - 20, other}, g.fn());
    }
    std::map<int, float> l{{kVirtualPlace, 1.f + u(rng)}};
    for (int id : wm) l[id] = 1.f + (u(rng) < 0.05f ? 20.f * u(rng) : 0.f);
    const auto a = cached.update(l, g.fn());
    const auto b = full.update(l, g.fn());
    ASSERT_EQ(a.size(), b.size());
    for (const auto& [id, p] : a) ASSERT_NEAR(p, b.at(id), 1e-6) << "t=" << t << " id=" << id;
  }
}

TEST(BayesFilter, PosteriorIsNormalised) {
  Graph g = chain(1, 5);
  BayesFilter filter;
  filter.update({{kVirtualPlace, 2.f}, {1, 1.f}, {2, 3.f}, {5, 1.f}}, g.fn());
  double sum = 0;
  for (const auto& [id, p] : filter.posterior()) sum += p;
  EXPECT_NEAR(sum, 1.0, 1e-6);
}

TEST(BayesFilter, RejectsBadInput) {
  Graph g = chain(1, 2);
  BayesFilter filter;
  EXPECT_THROW(filter.update({{1, 1.f}}, g.fn()), std::invalid_argument);
  EXPECT_THROW(filter.update({{kVirtualPlace, 1.f}, {1, std::nanf("")}}, g.fn()), std::invalid_argument);
  EXPECT_THROW(filter.update({{kVirtualPlace, 1.f}, {1, -1.f}}, g.fn()), std::invalid_argument);
  BayesFilterOptions bad;
  bad.predictionLC = {0.1f};
  std::string why;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("Bayes/PredictionLC"), std::string::npos);
  EXPECT_THROW(BayesFilter{bad}, std::invalid_argument);
}

// The flat form (the loop-closure detector's) and the map form give the same numbers, and the
// map views follow each update.
TEST(BayesFilter, FlatAndMapFormsAgree) {
  Graph g = chain(1, 40);
  BayesFilter flat, map;
  std::mt19937 rng(test::drawSeed(3));
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (int t = 0; t < 10; ++t) {
    Scores l{{kVirtualPlace, 1.f + u(rng)}};
    for (int id = 1 + t; id <= 30 + t; ++id) l.emplace_back(id, 1.f + (u(rng) < 0.1f ? 10.f * u(rng) : 0.f));
    const Scores& a = flat.updateScores(l, g.fn());
    const std::map<int, float>& b = map.update(toMap(l), g.fn());
    ASSERT_EQ(a.size(), b.size());
    for (const auto& [id, p] : a) ASSERT_EQ(p, b.at(id)) << "t=" << t << " id=" << id;
    EXPECT_EQ(flat.posterior(), b);  // the lazily built map view is this update's
    EXPECT_EQ(flat.prior(), map.prior());
  }
}

TEST(BayesFilter, RejectsUnsortedOrIncompleteScores) {
  Graph g = chain(1, 3);
  BayesFilter filter;
  EXPECT_THROW(filter.updateScores({{kVirtualPlace, 1.f}, {2, 1.f}, {1, 1.f}}, g.fn()), std::invalid_argument);
  EXPECT_THROW(filter.updateScores({{kVirtualPlace, 1.f}, {1, 1.f}, {1, 1.f}}, g.fn()), std::invalid_argument);
  EXPECT_THROW(filter.updateScores({{1, 1.f}, {kVirtualPlace, 1.f}}, g.fn()), std::invalid_argument);
  EXPECT_THROW(filter.updateScores({}, g.fn()), std::invalid_argument);
}

TEST(BayesFilter, OptionsFromParameters) {
  auto o = BayesFilterOptions::fromParameters({{"Bayes/PredictionLC", "0.2 0.5 0.3"},
                                               {"Bayes/VirtualPlacePriorThr", "0.8"}});
  EXPECT_FLOAT_EQ(o.virtualPlacePrior, 0.8f);
  ASSERT_EQ(o.predictionLC.size(), 3u);
  EXPECT_FLOAT_EQ(o.predictionLC[0], 0.2f);
  EXPECT_EQ(BayesFilterOptions::fromParameters({}).predictionLC.size(), 18u);
}

}  // namespace
}  // namespace rtabmap::bayes

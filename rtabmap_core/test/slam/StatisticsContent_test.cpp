// What an update's statistics hold, as Rtabmap/PublishStats, PublishPdf, PublishLikelihood and
// SaveWMState ask.
#include <gtest/gtest.h>

#include <algorithm>

#include "PoseOnlyFrames.h"
#include "TexturedFrames.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap {
namespace {

// Five nodes of different textures 0.5 m apart, a Short-Term Memory of one: Working Memory
// holds the older ones and the last update runs the Bayes filter over them.
Statistics lastStatistics(const ParametersMap& extra, std::vector<int>* workingMemory = nullptr) {
  Rtabmap slam;
  ParametersMap p = test::everyFrame();
  p["Mem/STMSize"] = "1";
  for (const auto& [k, v] : extra) p[k] = v;
  slam.init(p, "");
  for (int i = 0; i < 5; ++i) {
    EXPECT_TRUE(slam.process(test::texturedFrame(i + 1, i + 1.0, true, 10 + i), test::along(0.5 * i), test::smallCov()))
        << slam.lastRejection();
  }
  if (workingMemory) *workingMemory = slam.workingMemory();
  return slam.statistics();
}

TEST(StatisticsContent, ByDefaultThePosteriorAndTheLikelihoodButNotTheWorkingMemory) {
  const Statistics s = lastStatistics({});
  EXPECT_FALSE(s.posterior.empty());
  EXPECT_FALSE(s.likelihood.empty());
  EXPECT_TRUE(s.wmState.empty());
  EXPECT_FALSE(s.data().empty());
  EXPECT_GT(s.refImageId, 0);
}

TEST(StatisticsContent, EachPartAsAsked) {
  std::vector<int> wm;
  const Statistics s = lastStatistics({{"Rtabmap/PublishPdf", "false"},
                                       {"Rtabmap/PublishLikelihood", "false"},
                                       {"Rtabmap/SaveWMState", "true"},
                                       {"Rtabmap/PublishStats", "false"}},
                                      &wm);
  EXPECT_TRUE(s.posterior.empty());
  EXPECT_TRUE(s.likelihood.empty());
  std::sort(wm.begin(), wm.end());
  EXPECT_EQ(s.wmState, wm);
  EXPECT_EQ(s.wmState.size(), 5u);
  EXPECT_TRUE(s.data().empty());
  EXPECT_GT(s.refImageId, 0) << "the structured results stay";
}

}  // namespace
}  // namespace rtabmap

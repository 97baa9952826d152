#include <gtest/gtest.h>

#include <cctype>
#include <set>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/slam/Statistics.h"

namespace rtabmap {
namespace {

TEST(Statistics, GeneratedConstantsSpellTheOriginalKeys) {
  EXPECT_STREQ("Timing/Total/ms", Statistics::kTimingTotal);
  EXPECT_STREQ("Loop/Highest_hypothesis_id/", Statistics::kLoopHighest_hypothesis_id);
  EXPECT_STREQ("Memory/Working_memory_size/", Statistics::kMemoryWorking_memory_size);
  EXPECT_STREQ("Memory/Database_memory_used/MB", Statistics::kMemoryDatabase_memory_used);
  EXPECT_STREQ("Timing/Likelihood_computation/ms", Statistics::kTimingLikelihood_computation);
  EXPECT_STREQ("Loop/Accepted_hypothesis_id/", Statistics::kLoopAccepted_hypothesis_id);
}

TEST(Statistics, StandardKeysAreUniqueAndWellFormed) {
  const auto& keys = Statistics::standardKeys();
  ASSERT_GT(keys.size(), 50u);
  std::set<std::string> seen;
  for (const StatisticKey& k : keys) {
    SCOPED_TRACE(k.key);
    EXPECT_TRUE(seen.insert(k.key).second) << "duplicate key";
    std::string group, name, unit;
    ASSERT_TRUE(Statistics::parseKey(k.key, &group, &name, &unit));
    EXPECT_EQ(k.group, group);
    EXPECT_EQ(k.name, name);
    EXPECT_EQ(k.unit, unit);
    EXPECT_EQ(std::string(k.group) + "/" + k.name + "/" + k.unit, k.key);
    EXPECT_TRUE(std::isupper(static_cast<unsigned char>(group[0])));
    EXPECT_EQ(std::string::npos, std::string(k.key).find(' '));
    EXPECT_TRUE(Statistics::isStandardKey(k.key));
  }
  EXPECT_TRUE(seen.count("Timing/Memory_update/ms"));
  EXPECT_TRUE(seen.count("Timing/Posterior_computation/ms"));
  EXPECT_TRUE(seen.count("Timing/Map_optimization/ms"));
  EXPECT_TRUE(seen.count("Loop/Highest_hypothesis_value/"));
  EXPECT_TRUE(seen.count("Memory/Short_time_memory_size/"));
  EXPECT_FALSE(Statistics::isStandardKey("Timing/Total/s"));
}

TEST(Statistics, ParseKeySplitsGroupNameUnit) {
  std::string group, name, unit;
  EXPECT_TRUE(Statistics::parseKey("Odom/Camera/0/Features/", &group, &name, &unit));
  EXPECT_EQ("Odom", group);
  EXPECT_EQ("Camera/0/Features", name);
  EXPECT_EQ("", unit);
  EXPECT_EQ("ms", Statistics::unitOf("Timing/Total/ms"));
  EXPECT_FALSE(Statistics::parseKey("Timing/Total", nullptr, nullptr, nullptr));
  EXPECT_FALSE(Statistics::parseKey("/Total/ms", nullptr, nullptr, nullptr));
  EXPECT_FALSE(Statistics::parseKey("Timing//ms", nullptr, nullptr, nullptr));
  EXPECT_EQ("", Statistics::unitOf("nonsense"));
}

TEST(Statistics, AddStatisticAcceptsDynamicKeysAndRejectsMalformedOnes) {
  Statistics stats;
  stats.addStatistic(Statistics::kTimingTotal, 12.5f);
  stats.addStatistic("Custom/Camera_0_features/", 400.0f);
  float value = 0.0f;
  ASSERT_TRUE(stats.getStatistic("Timing/Total/ms", &value));
  EXPECT_EQ(12.5f, value);
  EXPECT_TRUE(stats.getStatistic("Custom/Camera_0_features/", nullptr));
  EXPECT_FALSE(stats.getStatistic(Statistics::kTimingMap_optimization, &value));
  EXPECT_THROW(stats.addStatistic("Total", 1.0f), FormatError);
  EXPECT_THROW(stats.setData({{"bad", 1.0f}}), FormatError);
  EXPECT_EQ(2u, stats.data().size());
  stats.setData({{Statistics::kLoopHighest_hypothesis_id, 7.0f}});
  EXPECT_EQ(1u, stats.data().size());
}

TEST(Statistics, ResultMembersStartEmpty) {
  Statistics stats;
  EXPECT_EQ(0, stats.refImageId);
  EXPECT_EQ(0, stats.loopClosureId);
  EXPECT_EQ(0, stats.proximityDetectionId);
  EXPECT_TRUE(stats.loopClosureTransform.isNull());
  EXPECT_TRUE(stats.posterior.empty());
  EXPECT_TRUE(stats.wmState.empty());
  stats.constraints.emplace(1, Link(1, 2, Link::kNeighbor, Transform::Identity()));
  EXPECT_EQ(1u, stats.constraints.size());
}

}  // namespace
}  // namespace rtabmap

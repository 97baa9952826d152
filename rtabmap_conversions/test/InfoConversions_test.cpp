#include "rtabmap_conversions/InfoConversions.h"

#include <gtest/gtest.h>

#include <limits>

using namespace rtabmap_conversions;
using rtabmap::Statistics;
using rtabmap::Transform;

namespace {

std_msgs::Header header() {
  std_msgs::Header h;
  h.frame_id = "map";
  h.stamp = ros::Time(1700000000, 123456789);
  return h;
}

}  // namespace

TEST(InfoConversions, StatisticsRoundTrip) {
  Statistics stats;
  stats.refImageId = 42;
  stats.loopClosureId = 7;
  stats.proximityDetectionId = 3;
  stats.landmarkId = -2;
  stats.loopClosureTransform = Transform(0.5, 0.1, 0.2);
  stats.wmState = {1, 2, 3, 42};
  stats.posterior = {{-1, 0.1f}, {7, 0.8f}};
  stats.likelihood = {{7, 2.5f}};
  stats.rawLikelihood = {{7, 0.3f}, {9, 0.01f}};
  stats.weights = {{1, 3}, {42, 0}};
  stats.labels = {{1, "start"}, {7, "door"}};
  stats.addStatistic(Statistics::kTimingTotal, 123.5f);
  stats.addStatistic(Statistics::kLoopHighest_hypothesis_id, 7.0f);
  stats.addStatistic("Custom/Sensor_timing/ms", 4.0f);
  const rtabmap_ros::Info msg = statisticsToMsg(stats, header());
  EXPECT_EQ(msg.refId, 42);
  EXPECT_EQ(msg.statsKeys.size(), 3u);
  EXPECT_EQ(msg.labelsValues, (std::vector<std::string>{"start", "door"}));
  std::string error;
  const std::optional<Statistics> back = statisticsFromMsg(msg, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->refImageId, 42);
  EXPECT_EQ(back->loopClosureId, 7);
  EXPECT_EQ(back->proximityDetectionId, 3);
  EXPECT_EQ(back->landmarkId, -2);
  EXPECT_TRUE(back->loopClosureTransform.toEigen().isApprox(stats.loopClosureTransform.toEigen(), 1e-12));
  EXPECT_EQ(back->wmState, stats.wmState);
  EXPECT_EQ(back->posterior, stats.posterior);
  EXPECT_EQ(back->likelihood, stats.likelihood);
  EXPECT_EQ(back->rawLikelihood, stats.rawLikelihood);
  EXPECT_EQ(back->weights, stats.weights);
  EXPECT_EQ(back->labels, stats.labels);
  EXPECT_EQ(back->data(), stats.data());
  EXPECT_DOUBLE_EQ(back->stamp, header().stamp.toSec());
}

TEST(InfoConversions, MismatchedArraysAndBadKeysAreErrors) {
  std::string error;
  Statistics stats;
  stats.posterior = {{1, 0.5f}};
  rtabmap_ros::Info msg = statisticsToMsg(stats, header());
  msg.posteriorValues.push_back(0.2f);
  EXPECT_FALSE(statisticsFromMsg(msg, &error));
  EXPECT_NE(error.find("posterior"), std::string::npos) << error;
  msg = statisticsToMsg(stats, header());
  msg.statsKeys = {"no-slashes"};
  msg.statsValues = {1.0f};
  EXPECT_FALSE(statisticsFromMsg(msg, &error));
  EXPECT_NE(error.find("no-slashes"), std::string::npos) << error;
}

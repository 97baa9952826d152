#include "rtabmap_conversions/InfoConversions.h"

#include "Support.h"
#include "rtabmap_conversions/TransformConversions.h"

namespace rtabmap_conversions {

namespace {

template <typename K, typename V, typename KeyVec, typename ValueVec>
void split(const std::map<K, V>& in, KeyVec& keys, ValueVec& values) {
  keys.clear();
  values.clear();
  keys.reserve(in.size());
  values.reserve(in.size());
  for (const auto& [k, v] : in) {
    keys.push_back(k);
    values.push_back(v);
  }
}

template <typename K, typename V, typename KeyVec, typename ValueVec>
bool join(const KeyVec& keys, const ValueVec& values, const char* name, std::map<K, V>& out, std::string* error) {
  if (keys.size() != values.size()) {
    detail::fail(error, std::string("Info ") + name + ": " + std::to_string(keys.size()) + " keys for " +
                            std::to_string(values.size()) + " values");
    return false;
  }
  for (size_t i = 0; i < keys.size(); ++i) out[keys[i]] = values[i];
  return true;
}

}  // namespace

rtabmap_ros::Info statisticsToMsg(const rtabmap::Statistics& stats, const std_msgs::Header& header) {
  rtabmap_ros::Info msg;
  msg.header = header;
  msg.refId = stats.refImageId;
  msg.loopClosureId = stats.loopClosureId;
  msg.proximityDetectionId = stats.proximityDetectionId;
  msg.landmarkId = stats.landmarkId;
  msg.loopClosureTransform = transformToMsg(stats.loopClosureTransform);
  msg.wmState.assign(stats.wmState.begin(), stats.wmState.end());
  split(stats.posterior, msg.posteriorKeys, msg.posteriorValues);
  split(stats.likelihood, msg.likelihoodKeys, msg.likelihoodValues);
  split(stats.rawLikelihood, msg.rawLikelihoodKeys, msg.rawLikelihoodValues);
  split(stats.weights, msg.weightsKeys, msg.weightsValues);
  split(stats.labels, msg.labelsKeys, msg.labelsValues);
  split(stats.data(), msg.statsKeys, msg.statsValues);
  return msg;
}

std::optional<rtabmap::Statistics> statisticsFromMsg(const rtabmap_ros::Info& msg, std::string* error) {
  rtabmap::Statistics stats;
  stats.refImageId = msg.refId;
  stats.loopClosureId = msg.loopClosureId;
  stats.proximityDetectionId = msg.proximityDetectionId;
  stats.landmarkId = msg.landmarkId;
  stats.loopClosureTransform = transformFromMsg(msg.loopClosureTransform);
  stats.stamp = msg.header.stamp.toSec();
  stats.wmState.assign(msg.wmState.begin(), msg.wmState.end());
  std::map<std::string, float> data;
  if (!join(msg.posteriorKeys, msg.posteriorValues, "posterior", stats.posterior, error) ||
      !join(msg.likelihoodKeys, msg.likelihoodValues, "likelihood", stats.likelihood, error) ||
      !join(msg.rawLikelihoodKeys, msg.rawLikelihoodValues, "rawLikelihood", stats.rawLikelihood, error) ||
      !join(msg.weightsKeys, msg.weightsValues, "weights", stats.weights, error) ||
      !join(msg.labelsKeys, msg.labelsValues, "labels", stats.labels, error) ||
      !join(msg.statsKeys, msg.statsValues, "statistics", data, error)) {
    return std::nullopt;
  }
  try {
    for (const auto& [key, value] : data) stats.addStatistic(key, value);
  } catch (const std::exception& e) {
    return detail::fail(error, std::string("Info statistics: ") + e.what());
  }
  return stats;
}

}  // namespace rtabmap_conversions

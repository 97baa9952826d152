#include "rtabmap_core/slam/Statistics.h"

#include <unordered_set>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {

const std::vector<StatisticKey>& Statistics::standardKeys() {
#define RTABMAP_STAT_ENTRY(Group, Name, Unit) \
  StatisticKey{k##Group##Name, #Group, #Name, #Unit},
  static const std::vector<StatisticKey> keys = {RTABMAP_STATISTICS_LIST(RTABMAP_STAT_ENTRY)};
#undef RTABMAP_STAT_ENTRY
  return keys;
}

bool Statistics::isStandardKey(const std::string& key) {
  static const std::unordered_set<std::string> set = [] {
    std::unordered_set<std::string> s;
    for (const StatisticKey& k : standardKeys()) s.insert(k.key);
    return s;
  }();
  return set.count(key) > 0;
}

bool Statistics::parseKey(const std::string& key, std::string* group, std::string* name,
                          std::string* unit) {
  const size_t first = key.find('/');
  const size_t last = key.rfind('/');
  if (first == std::string::npos || first == last) return false;
  if (first == 0 || last == first + 1) return false;  // empty group or name
  if (group) *group = key.substr(0, first);
  if (name) *name = key.substr(first + 1, last - first - 1);
  if (unit) *unit = key.substr(last + 1);
  return true;
}

std::string Statistics::unitOf(const std::string& key) {
  std::string unit;
  return parseKey(key, nullptr, nullptr, &unit) ? unit : std::string();
}

void Statistics::addStatistic(const std::string& key, float value) {
  if (!parseKey(key, nullptr, nullptr, nullptr)) {
    throw FormatError("statistic key \"" + key +
                      "\" is malformed: expected \"Group/Name/unit\" (unit may be empty, as in "
                      "\"Loop/Highest_hypothesis_id/\")");
  }
  data_[key] = value;
}

bool Statistics::getStatistic(const std::string& key, float* value) const {
  auto it = data_.find(key);
  if (it == data_.end()) return false;
  if (value) *value = it->second;
  return true;
}

void Statistics::setData(const std::map<std::string, float>& data) {
  // All keys checked first: a malformed one leaves the statistics unchanged.
  for (const auto& entry : data) {
    if (!parseKey(entry.first, nullptr, nullptr, nullptr)) addStatistic(entry.first, entry.second);
  }
  data_ = data;
}

}  // namespace rtabmap

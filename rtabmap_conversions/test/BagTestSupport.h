#pragma once
// Reading back bags in tests (what `rosbag info` and `rosbag play` see), and a scripted dataset
// reader that yields given records.
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <string>
#include <utility>
#include <vector>

#include "rtabmap_core/eval/DatasetReader.h"

namespace rtabmap_conversions::test {

class ScriptedReader : public rtabmap::DatasetReader {
 public:
  explicit ScriptedReader(std::vector<rtabmap::DatasetRecord> records) : records_(std::move(records)) {}
  std::string format() const override { return "scripted"; }
  bool next(rtabmap::DatasetRecord& record) override {
    if (next_ >= records_.size()) return false;
    record = records_[next_++];
    return true;
  }

 private:
  std::vector<rtabmap::DatasetRecord> records_;
  size_t next_ = 0;
};

template <typename M>
struct Stamped {
  ros::Time time;  // bag time
  M msg;
};

// Every message of a topic, in bag time order (as rosbag play would publish them).
template <typename M>
std::vector<Stamped<M>> readTopic(const std::string& path, const std::string& topic) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  std::vector<Stamped<M>> out;
  for (const rosbag::MessageInstance& m : view) {
    typename M::ConstPtr msg = m.instantiate<M>();
    if (msg) out.push_back({m.getTime(), *msg});
  }
  return out;
}

// Message count per topic, as `rosbag info` lists them.
inline std::map<std::string, size_t> topicCounts(const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::map<std::string, size_t> counts;
  for (const rosbag::ConnectionInfo* c : view.getConnections()) {
    counts[c->topic] += rosbag::View(bag, rosbag::TopicQuery(c->topic)).size();
  }
  return counts;
}

}  // namespace rtabmap_conversions::test

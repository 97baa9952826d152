#pragma once
// Throttles repeated log lines per text, not per call site: a stream of the same bad input
// logs once every `period` seconds, but a different problem is logged at once (ROS's
// *_THROTTLE macros would hide it behind the first one for the whole period).
#include <ros/time.h>

#include <map>
#include <mutex>
#include <string>

namespace rtabmap_sync {

class LogThrottle {
 public:
  explicit LogThrottle(double period = 5.0) : period_(period) {}

  // True when `key` (the message without stamps or counters) should be logged now.
  bool due(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::WallTime now = ros::WallTime::now();
    if (last_.size() > 100) last_.clear();  // keys come from input errors: keep the map small
    auto it = last_.find(key);
    if (it != last_.end() && (now - it->second).toSec() < period_) return false;
    last_[key] = now;
    return true;
  }

 private:
  double period_;
  std::mutex mutex_;
  std::map<std::string, ros::WallTime> last_;
};

}  // namespace rtabmap_sync

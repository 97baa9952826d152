#include "rtabmap_sync/DropCounter.h"

#include <algorithm>
#include <cmath>

namespace rtabmap_sync {

namespace {
// Intervals of the typical one: enough that a few outliers do not move it.
constexpr size_t kIntervals = 31;
// Intervals seen before gaps are counted: fewer do not give the rate yet.
constexpr size_t kMinIntervals = 5;
// An interval up to this many typical ones is jitter, not a lost message.
constexpr double kGapRatio = 1.5;
}  // namespace

DropCounter::DropCounter(size_t topics, size_t pendingLimit, bool unpairedAreDrops)
    : pendingLimit_(std::max<size_t>(pendingLimit, 1)), unpairedAreDrops_(unpairedAreDrops), topics_(topics) {}

double DropCounter::typicalInterval(size_t slot) const {
  const Topic& t = topics_.at(slot);
  if (t.intervals.size() < kMinIntervals) return 0.0;
  // The mean of the middle half: a median would take one side of an alternating jitter for
  // the rate (and the other side for gaps); the extremes are left out.
  std::vector<double> v(t.intervals.begin(), t.intervals.end());
  std::sort(v.begin(), v.end());
  const size_t q = v.size() / 4;
  double sum = 0.0;
  for (size_t i = q; i < v.size() - q; ++i) sum += v[i];
  return sum / double(v.size() - 2 * q);
}

void DropCounter::received(size_t slot, double stamp) {
  Topic& t = topics_.at(slot);
  if (t.hasLast && stamp > t.last) {
    const double interval = stamp - t.last;
    const double typical = typicalInterval(slot);
    if (typical > 0.0 && interval > kGapRatio * typical) {
      const long lost = std::lround(interval / typical) - 1;
      t.missing += lost;
      missing_ += lost;
    }
    // Gaps stay out of the typical interval: it is the rate the sensor sends at.
    if (!(typical > 0.0 && interval > kGapRatio * typical)) {
      t.intervals.push_back(interval);
      if (t.intervals.size() > kIntervals) t.intervals.pop_front();
    }
  }
  t.last = stamp;
  t.hasLast = true;
  t.pending.push_back(stamp);
  if (t.pending.size() > pendingLimit_) {
    t.pending.pop_front();
    countUnpaired(t);
  }
}

void DropCounter::delivered(const std::vector<double>& stamps) {
  for (size_t i = 0; i < stamps.size() && i < topics_.size(); ++i) {
    Topic& t = topics_[i];
    while (!t.pending.empty() && t.pending.front() < stamps[i]) {
      t.pending.pop_front();
      countUnpaired(t);
    }
    if (!t.pending.empty() && t.pending.front() == stamps[i]) t.pending.pop_front();
  }
}

void DropCounter::countUnpaired(Topic& t) {
  if (!unpairedAreDrops_) return;
  ++t.droppedInSync;
  ++droppedInSync_;
}

long DropCounter::setsLost() const {
  long most = 0;
  for (const Topic& t : topics_) most = std::max(most, t.droppedInSync + t.missing);
  return most;
}

void DropCounter::resetStamps() {
  for (Topic& t : topics_) {
    t.pending.clear();
    t.intervals.clear();
    t.hasLast = false;
  }
}

}  // namespace rtabmap_sync

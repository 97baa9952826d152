#pragma once
// Input the synchroniser lost, counted: message_filters and roscpp drop silently.
//  - In the synchroniser: a message accepted on a topic that no delivered set used, because a
//    set with a later stamp came out first (its partners were lost, or it waited beyond the
//    policy's queue). Found at each delivery: the topic's accepted stamps older than the set's.
//  - Before the node's callback: roscpp's subscriber queue (queue_size) drops the oldest message
//    when the node is busy longer than queue_size messages take to arrive (a slow SLAM update).
//    Such a message never reaches the node; it shows as a gap in the topic's stamps: an interval
//    of k typical intervals (a trimmed mean of the last ones) is k - 1 messages missing. A sensor that
//    stops sending shows the same way: the warning says both.
// Plain counting, no ROS: stamps in seconds.
#include <cstddef>
#include <deque>
#include <vector>

namespace rtabmap_sync {

class DropCounter {
 public:
  // topics: the synchronised topics; pendingLimit: accepted messages kept per topic waiting for
  // a set (beyond it the oldest counts as dropped, as the policy would have dropped it);
  // unpairedAreDrops: false for ApproximateTime, which leaves out the extra messages of a
  // faster topic by design (only gaps in the stamps count then).
  explicit DropCounter(size_t topics = 0, size_t pendingLimit = 100, bool unpairedAreDrops = true);

  // A message of topic `slot` accepted, stamps increasing per topic.
  void received(size_t slot, double stamp);
  // A set delivered: the stamp of its message of each topic, in slot order.
  void delivered(const std::vector<double>& stamps);
  // After a restart of time (a replayed bag): forget the stamps, keep the counts.
  void resetStamps();

  long droppedInSync() const { return droppedInSync_; }
  long missingFromStamps() const { return missing_; }
  long dropped() const { return droppedInSync_ + missing_; }
  // Sets lost, estimated: the most messages lost on one topic (a set needs one of each).
  long setsLost() const;
  // Per topic.
  long droppedInSync(size_t slot) const { return topics_.at(slot).droppedInSync; }
  long missingFromStamps(size_t slot) const { return topics_.at(slot).missing; }
  double typicalInterval(size_t slot) const;  // 0 until known

 private:
  struct Topic {
    std::deque<double> pending;    // accepted, not yet in a delivered set
    std::deque<double> intervals;  // the last stamp intervals, for the typical one
    double last = 0.0;
    bool hasLast = false;
    long droppedInSync = 0, missing = 0;
  };
  void countUnpaired(Topic& t);

  size_t pendingLimit_;
  bool unpairedAreDrops_;
  std::vector<Topic> topics_;
  long droppedInSync_ = 0, missing_ = 0;
};

}  // namespace rtabmap_sync

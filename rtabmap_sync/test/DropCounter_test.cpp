// Input lost silently by roscpp's subscriber queues and message_filters, counted (the soak lost
// 3% of its frames while the SLAM node was busy, and nothing said so).
#include <gtest/gtest.h>

#include "rtabmap_sync/DropCounter.h"

namespace rtabmap_sync {
namespace {

// Three topics of one sensor at 1 Hz, exact stamps (ExactTime), every set delivered.
TEST(DropCounter, NothingLostCountsNothing) {
  DropCounter d(3, 12);
  for (int i = 0; i < 50; ++i) {
    for (size_t s = 0; s < 3; ++s) d.received(s, 100.0 + i);
    d.delivered({100.0 + i, 100.0 + i, 100.0 + i});
  }
  EXPECT_EQ(d.dropped(), 0);
  EXPECT_EQ(d.setsLost(), 0);
  EXPECT_DOUBLE_EQ(d.typicalInterval(0), 1.0);
}

// roscpp's queue overflowed while the node was busy: frames 20 and 21 never arrived on any
// topic, frame 35 only on topic 1. Frame 35's other message waited, then a later set came out.
TEST(DropCounter, GapsInTheStampsAndUnpairedMessagesAreDrops) {
  DropCounter d(2, 12);
  for (int i = 0; i < 50; ++i) {
    const double t = 0.5 * i;  // 2 Hz
    if (i == 20 || i == 21) continue;
    if (i == 35) {
      d.received(0, t);  // its partner on topic 1 was lost
      continue;
    }
    d.received(0, t);
    d.received(1, t);
    d.delivered({t, t});
  }
  EXPECT_EQ(d.missingFromStamps(0), 2);
  EXPECT_EQ(d.missingFromStamps(1), 3);
  EXPECT_EQ(d.droppedInSync(0), 1);  // frame 35 of topic 0, overtaken by frame 36's set
  EXPECT_EQ(d.droppedInSync(1), 0);
  EXPECT_EQ(d.setsLost(), 3);  // 20, 21, 35
  EXPECT_EQ(d.dropped(), 6);
}

// Jitter is not loss; the rate is learnt from the stamps, gaps left out of it.
TEST(DropCounter, JitterAndALongSilence) {
  DropCounter d(1);
  double t = 0.0;
  for (int i = 0; i < 100; ++i) {
    t += (i % 2) ? 0.13 : 0.07;  // 10 Hz with +-30 ms jitter
    d.received(0, t);
    d.delivered({t});
  }
  EXPECT_EQ(d.dropped(), 0);
  t += 3.0;  // the sensor stopped for 3 s: about 29 messages it did not send
  d.received(0, t);
  EXPECT_NEAR(d.missingFromStamps(0), 29, 1);
  EXPECT_NEAR(d.typicalInterval(0), 0.1, 0.031);
}

// ApproximateTime pairs a 10 Hz camera with a 40 Hz laser: the laser's extra messages are left
// out by design, not lost.
TEST(DropCounter, ApproximateTimeLeavesOutExtraMessagesByDesign) {
  DropCounter d(2, 12, false);
  for (int i = 0; i < 400; ++i) {
    const double laser = 0.025 * i;
    d.received(1, laser);
    if (i % 4 == 0) {
      d.received(0, laser + 0.001);
      d.delivered({laser + 0.001, laser});
    }
  }
  EXPECT_EQ(d.dropped(), 0);
  DropCounter exact(2, 12, true);
  for (int i = 0; i < 40; ++i) {
    exact.received(1, 0.025 * i);
    if (i % 4 == 0) {
      exact.received(0, 0.025 * i);
      exact.delivered({0.025 * i, 0.025 * i});
    }
  }
  EXPECT_EQ(exact.droppedInSync(1), 27);  // 30 extra laser messages, the last 3 still waiting
}

// A topic whose partners never come: the policy keeps queue_size of them, the rest are lost;
// a restart of time (bag replayed again) is not a gap.
TEST(DropCounter, PendingLimitAndTimeRestart) {
  DropCounter d(2, 5);
  for (int i = 0; i < 20; ++i) d.received(0, 1.0 * i);
  EXPECT_EQ(d.droppedInSync(0), 15);
  d.resetStamps();
  for (int i = 0; i < 10; ++i) {
    d.received(0, 1.0 * i);
    d.received(1, 1.0 * i);
    d.delivered({1.0 * i, 1.0 * i});
  }
  EXPECT_EQ(d.missingFromStamps(), 0);
  EXPECT_EQ(d.droppedInSync(0), 15);
}

}  // namespace
}  // namespace rtabmap_sync

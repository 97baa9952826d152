// Algorithm 1 end to end on synthetic places: revisits are recognised, nothing else is, and
// with a bounded Working Memory the revisited places come back from the LTM by retrieval.
#include "rtabmap_core/memory/LoopClosureDetector.h"

#include <gtest/gtest.h>

#include "MemoryTestPlaces.h"
#include "common/TestData.h"
#include "rtabmap_core/db/Database.h"

namespace rtabmap::memory {
namespace {

using test::view;

struct DriveResult {
  int accepted = 0, correct = 0, revisits = 0;
  size_t maxWm = 0;
  int retrieved = 0, transferred = 0;
};

// Places 1..60 (pausing at every 6th: a second view merged by rehearsal raises its weight),
// then back over places 20..45. placeOf maps location ids to places.
DriveResult drive(LoopClosureDetector& d) {
  DriveResult run;
  std::map<int, int> placeOf;
  for (int p = 1; p <= 60; ++p) {
    auto u = d.process(view(p, 0, 100, 15));
    placeOf[u.id] = p;
    EXPECT_EQ(u.loopClosureId, 0) << "place " << p << " is new";
    if (p % 6 == 0) {
      EXPECT_TRUE(d.process(view(p, 1, 100, 15)).merged);
    }
    run.maxWm = std::max(run.maxWm, d.memory().wm().size());
  }
  for (int p = 20; p <= 45; ++p) {
    auto u = d.process(view(p, 2, 100, 15));
    ++run.revisits;
    run.retrieved += static_cast<int>(u.retrieved.size());
    run.transferred += static_cast<int>(u.transferred.size());
    run.maxWm = std::max(run.maxWm, d.memory().wm().size());
    if (u.loopClosureId) {
      ++run.accepted;
      EXPECT_EQ(placeOf[u.loopClosureId], p) << "false loop closure at revisit of place " << p;
      run.correct += placeOf[u.loopClosureId] == p;
    }
  }
  return run;
}

TEST(LoopClosureDetector, RecognisesRevisitedPlacesAndNothingElse) {
  LoopClosureDetector d(LoopClosureDetectorOptions::fromParameters({}), nullptr);
  DriveResult run = drive(d);
  EXPECT_EQ(run.accepted, run.correct);
  EXPECT_GE(run.accepted, run.revisits - 2);  // the first revisits build up the posterior
}

TEST(LoopClosureDetector, BoundedWorkingMemoryStillClosesLoopsThroughRetrieval) {
  rtabmap::test::TempDir dir;
  db::Database ltm(dir.file("ltm.db"));
  auto options = LoopClosureDetectorOptions::fromParameters({{"Rtabmap/MemoryThr", "15"}});
  LoopClosureDetector d(options, &ltm);
  DriveResult run = drive(d);
  EXPECT_LE(run.maxWm, 16u);  // the threshold, plus this update's retrieval before transfer
  EXPECT_GT(run.retrieved, 10);
  EXPECT_GT(run.transferred, 10);
  EXPECT_EQ(run.accepted, run.correct);
  // Revisited places in LTM are recognised once a weighted place of the area (kept in WM)
  // brings its neighbours back.
  EXPECT_GE(run.accepted, run.revisits / 2);
}

TEST(LoopClosureDetector, TimingsAndSizesAreReported) {
  LoopClosureDetector d(LoopClosureDetectorOptions::fromParameters({{"Mem/STMSize", "1"}}), nullptr);
  d.process(view(1));
  d.process(view(2));
  auto u = d.process(view(3), true);
  EXPECT_EQ(u.wmSize, 2);
  EXPECT_EQ(u.stmSize, 1);
  EXPECT_EQ(u.vocabularySize, 300);
  EXPECT_GT(u.totalMs, 0.0);
  EXPECT_GE(u.totalMs, u.memoryUpdateMs);
  EXPECT_EQ(u.posterior.size(), 3u);  // virtual place + WM 1, 2
}

}  // namespace
}  // namespace rtabmap::memory

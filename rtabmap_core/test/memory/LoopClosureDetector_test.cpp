// Algorithm 1 end to end on synthetic places: revisits are recognised, nothing else is, and
// with a bounded Working Memory the revisited places come back from the LTM by retrieval.
#include "rtabmap_core/memory/LoopClosureDetector.h"

#include <gtest/gtest.h>

#include <random>

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

// A view of place p whose keypoints are its 100 points (3-8 m ahead) projected from a camera
// moved by `visit` (f 500, 640 x 480); an alias has the place's words where another scene would
// put them (the keypoints shuffled), as a building's repeated rooms look to a bag of words.
LocationInput geometricView(int place, int visit, bool alias) {
  LocationInput in = view(place, visit, 100, 15);
  cv::RNG rng(static_cast<uint64_t>(500 + place));
  const float yaw = 0.05f * static_cast<float>(visit), c = std::cos(yaw), s = std::sin(yaw);
  for (auto& kp : in.keypoints) {
    const float x = rng.uniform(-2.5f, 2.5f), y = rng.uniform(-1.8f, 1.8f), z = rng.uniform(3.f, 8.f);
    const float cx = c * x + s * z + 0.2f * static_cast<float>(visit), cz = -s * x + c * z - 0.3f * static_cast<float>(visit);
    kp.pt = {500.f * cx / cz + 320.f, 500.f * y / cz + 240.f};
  }
  if (alias) std::shuffle(in.keypoints.begin(), in.keypoints.end(), std::mt19937(static_cast<unsigned>(place)));
  return in;
}

struct RevisitResult {
  int accepted = 0, correct = 0, refusedByEpipolarGeometry = 0;
};

// Places 1..40, then places 10..25 again, as true views or as aliases.
RevisitResult revisit(bool epipolarCheck, bool alias) {
  LoopClosureDetector d(LoopClosureDetectorOptions::fromParameters({{"VhEp/Enabled", epipolarCheck ? "true" : "false"}}),
                        nullptr);
  std::map<int, int> placeOf;
  for (int p = 1; p <= 40; ++p) placeOf[d.process(geometricView(p, 0, false)).id] = p;
  RevisitResult r;
  for (int p = 10; p <= 25; ++p) {
    const auto u = d.process(geometricView(p, 1, alias));
    if (u.loopClosureId) {
      ++r.accepted;
      r.correct += placeOf[u.loopClosureId] == p;
    }
    r.refusedByEpipolarGeometry += u.highest.rejectedBecause.find("epipolar") != std::string::npos;
  }
  return r;
}

TEST(LoopClosureDetector, EpipolarCheckKeepsTrueRevisits) {
  const RevisitResult r = revisit(true, false);
  EXPECT_GE(r.accepted, 14);  // of 16: the first revisits build up the posterior
  EXPECT_EQ(r.correct, r.accepted);
  EXPECT_EQ(r.refusedByEpipolarGeometry, 0);
}

TEST(LoopClosureDetector, EpipolarCheckRefusesAliasesTheBagOfWordsAccepts) {
  const RevisitResult without = revisit(false, true);
  EXPECT_GE(without.accepted, 14) << "the words alone cannot tell an alias";
  const RevisitResult with = revisit(true, true);
  EXPECT_EQ(with.accepted, 0);
  EXPECT_GE(with.refusedByEpipolarGeometry, 14);
}

TEST(LoopClosureDetector, TimingsAndSizesAreReported) {
  // Exact nearest neighbours (Kp/NNStrategy 0): the kd-trees' approximate search, built from
  // std::random_device in Debian's FLANN, sometimes quantises a descriptor to another place's
  // word and the vocabulary is then 299.
  LoopClosureDetector d(LoopClosureDetectorOptions::fromParameters({{"Mem/STMSize", "1"}, {"Kp/NNStrategy", "0"}}),
                        nullptr);
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

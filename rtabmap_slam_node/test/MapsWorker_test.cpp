// The maps worker (MapsWorker.h) and its owner's side (MapsHandover.h): jobs coalesce instead of
// queueing, submit() never waits for an assembly, clear() and stop() leave nothing of the old
// maps published, and the maps end up as a synchronous MapsAssembler makes them. The threaded
// tests also run under ThreadSanitizer (MapsWorker.h notes; README: make test-tsan).
#include "rtabmap_slam_node/MapsWorker.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <future>
#include <mutex>
#include <thread>
#include <vector>

#include "TestGrids.h"
#include "rtabmap_slam_node/MapsHandover.h"

namespace rtabmap_slam_node {
namespace {

using rtabmap::Transform;
using namespace std::chrono_literals;

using test::wallAhead;

MapsWanted cloudOnly() {
  MapsWanted w;
  w.cloud = true;
  return w;
}

MapsWanted cloudAndOctomap() {
  MapsWanted w = cloudOnly();
  w.octomap = true;
  return w;
}

// Nodes 1..n, 2 m apart along x.
std::map<int, Transform> line(int n, float y = 0.0f) {
  std::map<int, Transform> poses;
  for (int id = 1; id <= n; ++id) poses[id] = Transform(2.0f * id, y, 0, 0, 0, 0);
  return poses;
}

// A job with the poses of `line(n)` and a grid for each node in [firstGrid, n].
MapsJob jobOf(int n, int firstGrid, std::int64_t stamp, float y = 0.0f) {
  MapsJob job;
  job.poses = line(n, y);
  for (int id = firstGrid; id <= n; ++id) job.grids[id] = wallAhead();
  job.wanted = cloudOnly();
  job.stampNs = stamp;
  job.frameId = "map";
  return job;
}

// What the worker published, with an optional gate that holds prepare() or the publish itself.
class FakeSink : public MapsSink {
 public:
  struct Published {
    std::int64_t stampNs;
    int cloudNodes;
    size_t cloudPoints;
    std::string frameId;
  };

  std::function<void()> prepare(const MapsAssembler& maps, const MapsUpdateSummary& summary,
                                const MapsJob& job) override {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      workerNice_ = ::getpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)));
      ++prepared_;
      changed_.notify_all();
      changed_.wait(lock, [this] { return !holdPrepare_; });
    }
    Published p{job.stampNs, summary.cloudNodes, maps.cloudMap() ? maps.cloudMap()->cloud().size() : 0, job.frameId};
    return [this, p] {
      std::unique_lock<std::mutex> lock(mutex_);
      ++sending_;
      changed_.notify_all();
      changed_.wait(lock, [this] { return !holdSend_; });
      published_.push_back(p);
    };
  }

  void hold(bool prepare, bool send) {
    std::lock_guard<std::mutex> lock(mutex_);
    holdPrepare_ = prepare;
    holdSend_ = send;
    changed_.notify_all();
  }
  bool waitPrepared(int n) { return waitFor([&] { return prepared_ >= n; }); }
  bool waitSending(int n) { return waitFor([&] { return sending_ >= n; }); }
  std::vector<Published> published() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return published_;
  }
  int workerNice() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return workerNice_;
  }

 private:
  template <class P>
  bool waitFor(P done) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, 10s, done);
  }
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  bool holdPrepare_ = false, holdSend_ = false;
  int prepared_ = 0, sending_ = 0;
  int workerNice_ = -100;
  std::vector<Published> published_;
};

TEST(MapsJob, MergeKeepsTheNewestPosesAndEveryGrid) {
  MapsJob older = jobOf(2, 1, 10);
  older.force = true;
  older.invalidated = {1};
  MapsJob newer = jobOf(3, 3, 20, 1.0f);
  newer.grids[1] = std::nullopt;  // node 1's grid handed again: the newer word wins
  newer.invalidated = {2};
  newer.wanted = cloudAndOctomap();
  older.merge(std::move(newer));
  EXPECT_EQ(older.poses, line(3, 1.0f));
  EXPECT_EQ(older.stampNs, 20);
  EXPECT_TRUE(older.wanted.octomap);
  EXPECT_TRUE(older.force) << "the older job's new subscriber still waits for its maps";
  ASSERT_EQ(older.grids.size(), 3u);
  EXPECT_FALSE(older.grids.at(1));
  EXPECT_TRUE(older.grids.at(2) && older.grids.at(3));
  EXPECT_EQ(older.invalidated, (std::set<int>{1, 2}));
}

TEST(MapsWorker, AssemblesAndPublishesOffTheCallersThread) {
  FakeSink sink;
  MapsWorker worker(sink);
  worker.submit(jobOf(3, 1, 100));
  ASSERT_TRUE(worker.waitIdle(10s));
  const std::vector<FakeSink::Published> out = sink.published();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].stampNs, 100);
  EXPECT_EQ(out[0].frameId, "map");
  EXPECT_EQ(out[0].cloudNodes, 3);
  EXPECT_GT(out[0].cloudPoints, 3u * 100u);
  const MapsWorkerStats s = worker.stats();
  EXPECT_EQ(s.last.cloudNodes, 3);
  EXPECT_EQ(s.last.graphNodes, 3);
  EXPECT_EQ(s.last.gridsFetched, 3);
  EXPECT_GT(s.last.timeMs, 0.0);
  EXPECT_EQ(s.completedJobs, 1);
  EXPECT_EQ(s.assemblingUpdates, 1);
  EXPECT_EQ(s.coalescedJobs, 0);
  // Behind the SLAM update's threads (capped at 19 if the test itself runs niced).
  const int mine = ::getpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)));
  EXPECT_EQ(sink.workerNice(), std::min(19, mine + MapsWorker::kNiceIncrement));
}

TEST(MapsWorker, JobsCoalesceWhileBusyAndSubmitNeverWaits) {
  FakeSink sink;
  MapsWorker worker(sink);
  sink.hold(true, false);
  worker.submit(jobOf(2, 1, 1));
  ASSERT_TRUE(sink.waitPrepared(1));  // the worker is busy with job 1
  // Two more updates while it is held: they return at once and become one pending job.
  const auto start = std::chrono::steady_clock::now();
  worker.submit(jobOf(3, 3, 2));
  worker.submit(jobOf(4, 4, 3, 0.5f));
  EXPECT_LT(std::chrono::steady_clock::now() - start, 1s) << "submit() waited for the assembly";
  EXPECT_EQ(worker.stats().coalescedJobs, 1);
  EXPECT_EQ(worker.stats().completedJobs, 0);
  EXPECT_EQ(worker.stats().last.cloudNodes, 0) << "statistics of an assembly not completed yet";
  sink.hold(false, false);
  ASSERT_TRUE(worker.waitIdle(10s));
  const std::vector<FakeSink::Published> out = sink.published();
  ASSERT_EQ(out.size(), 2u) << "3 updates, 2 assemblies";
  EXPECT_EQ(out[0].cloudNodes, 2);
  EXPECT_EQ(out[1].stampNs, 3) << "the newest header wins";
  EXPECT_EQ(out[1].cloudNodes, 4) << "grids of both merged jobs were kept";
  EXPECT_EQ(worker.stats().last.gridsFetched, 2);
  EXPECT_EQ(worker.stats().completedJobs, 2);
}

TEST(MapsWorker, AGridHandedBeforeItsNodeHasAPoseWaitsForIt) {
  FakeSink sink;
  MapsWorker worker(sink);
  MapsJob job = jobOf(1, 1, 1);
  job.grids[2] = wallAhead();  // node 2 left the optimised graph (e.g. to long-term memory)
  worker.submit(std::move(job));
  ASSERT_TRUE(worker.waitIdle(10s));
  EXPECT_EQ(worker.stats().last.cloudNodes, 1);
  worker.submit(jobOf(2, 3, 2));  // back in the graph, its grid not handed again
  ASSERT_TRUE(worker.waitIdle(10s));
  EXPECT_EQ(worker.stats().last.cloudNodes, 2);
  EXPECT_EQ(worker.stats().last.gridsFetched, 1);
}

TEST(MapsWorker, NothingOfTheOldMapsIsPublishedAfterClear) {
  FakeSink sink;
  MapsWorker worker(sink);
  sink.hold(true, false);
  worker.submit(jobOf(3, 1, 1));
  ASSERT_TRUE(sink.waitPrepared(1));
  worker.submit(jobOf(4, 4, 2));  // pending: dropped by clear()
  worker.clear();                 // returns although job 1 is under way (not publishing yet)
  EXPECT_EQ(worker.stats().last.cloudNodes, 0);
  sink.hold(false, false);
  ASSERT_TRUE(worker.waitIdle(10s));
  EXPECT_TRUE(sink.published().empty()) << "a job of before clear() was published";
  EXPECT_EQ(worker.stats().discardedJobs, 2);
  EXPECT_EQ(worker.stats().completedJobs, 0);

  // The maps start again from what comes after: node 1 only, its grid handed again.
  worker.submit(jobOf(1, 1, 3));
  ASSERT_TRUE(worker.waitIdle(10s));
  ASSERT_EQ(sink.published().size(), 1u);
  EXPECT_EQ(sink.published()[0].cloudNodes, 1) << "nodes 2 and 3 of the old maps survived clear()";
}

TEST(MapsWorker, ClearWaitsForAPublishUnderWay) {
  FakeSink sink;
  MapsWorker worker(sink);
  sink.hold(false, true);
  worker.submit(jobOf(2, 1, 1));
  ASSERT_TRUE(sink.waitSending(1));  // past the generation check, inside the publish
  std::future<void> cleared = std::async(std::launch::async, [&] { worker.clear(); });
  EXPECT_EQ(cleared.wait_for(200ms), std::future_status::timeout) << "clear() returned during a publish";
  sink.hold(false, false);
  EXPECT_EQ(cleared.wait_for(10s), std::future_status::ready);
  ASSERT_EQ(sink.published().size(), 1u);  // it had started: it ends, before clear() returns
}

TEST(MapsWorker, ClearWithNewOptionsReplacesTheAssembler) {
  FakeSink sink;
  MapsWorker worker(sink);
  worker.submit(jobOf(2, 1, 1));
  ASSERT_TRUE(worker.waitIdle(10s));
  const size_t fine = sink.published().back().cloudPoints;
  worker.clear(MapsAssembler(rtabmap::ParametersMap{{"Grid/CellSize", "0.2"}}));  // coarser voxels: fewer points
  worker.submit(jobOf(2, 1, 2));
  ASSERT_TRUE(worker.waitIdle(10s));
  EXPECT_LT(sink.published().back().cloudPoints, fine);
  EXPECT_EQ(worker.stats().assemblingUpdates, 2) << "counted since start, across assemblers";
}

TEST(MapsWorker, StopJoinsAndDropsWhatIsLeft) {
  FakeSink sink;
  auto worker = std::make_unique<MapsWorker>(sink);
  sink.hold(true, false);
  worker->submit(jobOf(2, 1, 1));
  ASSERT_TRUE(sink.waitPrepared(1));
  worker->submit(jobOf(3, 3, 2));
  std::future<void> stopped = std::async(std::launch::async, [&] { worker->stop(); });
  EXPECT_EQ(stopped.wait_for(100ms), std::future_status::timeout) << "stop() did not wait for the thread";
  sink.hold(false, false);
  ASSERT_EQ(stopped.wait_for(10s), std::future_status::ready);
  worker->submit(jobOf(4, 4, 3));  // ignored
  worker.reset();                  // a second stop(): nothing left to join
  EXPECT_TRUE(sink.published().empty()) << "published while stopping";
}

// ---------------------------------------------------------------------------------------------
// The owner's side.

struct Source {
  std::map<int, rtabmap::LocalGrid> grids;
  std::vector<int> asked;
  MapsAssembler::GridSource fn() {
    return [this](int id) -> std::optional<rtabmap::LocalGrid> {
      asked.push_back(id);
      auto it = grids.find(id);
      if (it == grids.end()) return std::nullopt;
      return it->second;
    };
  }
};

TEST(MapsHandover, HandsEachGridOnceUntilAMapIsGained) {
  Source source;
  for (int id = 1; id <= 4; ++id) source.grids[id] = wallAhead();
  MapsHandover handover;
  EXPECT_FALSE(handover.makeJob(line(3), MapsWanted(), false, source.fn())) << "a job with nobody listening";
  EXPECT_TRUE(source.asked.empty());

  std::optional<MapsJob> job = handover.makeJob(line(3), cloudOnly(), true, source.fn());
  ASSERT_TRUE(job);
  EXPECT_EQ(job->grids.size(), 3u) << "the first wanted map starts from every node";
  EXPECT_TRUE(job->force);
  job = handover.makeJob(line(4), cloudOnly(), false, source.fn());
  ASSERT_EQ(job->grids.size(), 1u) << "only the new node";
  EXPECT_TRUE(job->grids.count(4));
  EXPECT_EQ(job->poses.size(), 4u);

  job = handover.makeJob(line(4), cloudAndOctomap(), true, source.fn());  // octomap subscribed
  EXPECT_EQ(job->grids.size(), 4u) << "the octomap must be built from the whole graph";
  job = handover.makeJob(line(4), cloudOnly(), false, source.fn());  // octomap unsubscribed
  EXPECT_TRUE(job->grids.empty());

  job = handover.makeJob(line(4), MapsWanted(), false, source.fn());  // nobody left
  ASSERT_TRUE(job) << "one job to drop the maps";
  EXPECT_FALSE(job->wanted.any());
  EXPECT_FALSE(handover.makeJob(line(5), MapsWanted(), false, source.fn()));
  EXPECT_EQ(source.asked.size(), 3u + 1u + 4u);

  job = handover.makeJob(line(4), cloudOnly(), false, source.fn());
  EXPECT_EQ(job->grids.size(), 4u) << "listened again: everything again";
}

TEST(MapsHandover, InvalidatedGridsAreHandedAgainAndCopiesOwnTheirCells) {
  Source source;
  source.grids[1] = wallAhead();
  MapsHandover handover;
  std::optional<MapsJob> job = handover.makeJob(line(2), cloudOnly(), false, source.fn());
  ASSERT_EQ(job->grids.size(), 2u);
  EXPECT_FALSE(job->grids.at(2)) << "node 2 has no grid";
  const rtabmap::LocalGrid& handed = *job->grids.at(1);
  EXPECT_NE(handed.obstacles.data, source.grids[1].obstacles.data) << "the worker shares the owner's cells";
  EXPECT_TRUE(sameLocalGrid(handed, source.grids[1]));

  source.grids[2] = wallAhead();
  handover.invalidate(2);
  job = handover.makeJob(line(2), cloudOnly(), false, source.fn());
  EXPECT_EQ(job->invalidated, std::set<int>{2});
  ASSERT_EQ(job->grids.size(), 1u);
  EXPECT_TRUE(job->grids.at(2));
  job = handover.makeJob(line(2), cloudOnly(), false, source.fn());
  EXPECT_TRUE(job->invalidated.empty() && job->grids.empty());
}

// The owner hands a growing, re-optimised graph over while the worker assembles and a third
// thread reads statistics; a clear() in the middle (another map reusing the node ids). At the
// end the worker's published cloud is the one a synchronous MapsAssembler makes of the last
// graph. Under ThreadSanitizer this is the race check of the whole hand-over.
TEST(MapsWorker, ConcurrentUpdatesEndWithTheSynchronousMaps) {
  FakeSink sink;
  MapsWorker worker(sink);
  MapsHandover handover;
  Source source;
  std::atomic<bool> done{false};
  std::thread reader([&] {
    while (!done) {
      const MapsWorkerStats s = worker.stats();
      EXPECT_LE(s.last.cloudNodes, 40);
      std::this_thread::yield();
    }
  });
  std::map<int, Transform> poses;
  for (int update = 1; update <= 40; ++update) {
    if (update == 20) {  // a new map: ids start again, other grids
      worker.clear();
      handover.clear();
      poses.clear();
      source.grids.clear();
    }
    const int id = update < 20 ? update : update - 19;
    source.grids[id] = wallAhead();
    // Every node moves a little at each update (loop closures re-optimise the graph).
    poses[id] = Transform(2.0f * id, 0, 0, 0, 0, 0);
    for (auto& [n, pose] : poses) pose = Transform(2.0f * n, 0.01f * update, 0, 0, 0, 0);
    std::optional<MapsJob> job = handover.makeJob(poses, cloudOnly(), false, source.fn());
    ASSERT_TRUE(job);
    job->stampNs = update;
    worker.submit(std::move(*job));
    std::this_thread::sleep_for(1ms);
  }
  ASSERT_TRUE(worker.waitIdle(30s));
  done = true;
  reader.join();

  MapsAssembler reference;
  reference.update(poses, cloudOnly(), source.fn());
  const std::vector<FakeSink::Published> out = sink.published();
  ASSERT_FALSE(out.empty());
  EXPECT_EQ(out.back().stampNs, 40);
  EXPECT_EQ(out.back().cloudNodes, 21);
  EXPECT_EQ(out.back().cloudPoints, reference.cloudMap()->cloud().size());
  for (size_t i = 1; i < out.size(); ++i) EXPECT_GT(out[i].stampNs, out[i - 1].stampNs) << "published out of order";
  const MapsWorkerStats s = worker.stats();
  EXPECT_EQ(s.completedJobs + s.coalescedJobs + s.discardedJobs, 40) << "every update is accounted for";
  EXPECT_EQ(s.completedJobs, static_cast<long>(out.size()));
  EXPECT_EQ(s.last.graphNodes, 21);
}

}  // namespace
}  // namespace rtabmap_slam_node

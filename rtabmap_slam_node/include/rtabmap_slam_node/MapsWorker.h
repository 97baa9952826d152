#pragma once
// The 3D maps assembled off the owner's thread: the SLAM nodelet (and map_assembler) hands a
// job per update (MapsHandover.h makes it under the owner's lock: the optimised poses and only
// the local grids the maps have not received) and returns at once; one worker thread brings the
// MapsAssembler to it and has a MapsSink make and publish the messages.
//
// Never a growing queue and never a blocked update: a job submitted while the worker is busy
// waits as the one pending job, and a later one merges into it (the newest poses, wanted maps
// and header win; grids and invalidations accumulate; a forced publish stays forced). Only the
// assembly finishing first is ever waited for, by clear() and stop(), never by submit().
//
// clear() (another core, database or parameters): drops the pending job and the maps; once it
// returns no job submitted before it publishes anything (a job under way finishes its assembly
// into the old maps, then is discarded instead of published). ROS-free: the sink is an
// interface, a fake one in the tests.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>

#include "rtabmap_slam_node/MapsAssembler.h"

namespace rtabmap_slam_node {

// One update's work for the worker.
struct MapsJob {
  std::map<int, rtabmap::Transform> poses;  // the graph's optimised poses (map frame)
  // Grids handed over with this job: nodes the maps had not received, or whose grid changed.
  // nullopt: the node has none (not asked again).
  std::map<int, std::optional<rtabmap::LocalGrid>> grids;
  std::set<int> invalidated;  // nodes whose earlier grid is obsolete (their new one is in grids)
  MapsWanted wanted;          // decided by the owner when it made the job (see MapsHandover)
  bool force = false;         // publish every wanted map, changed or not (a new subscriber)
  std::string frameId;        // header of the messages
  std::int64_t stampNs = 0;

  // `newer` arrived while this one was still waiting: one job doing both.
  void merge(MapsJob&& newer);
};

// Makes the messages of the maps (on the worker thread, outside every lock), then publishes them
// when the returned function is called (under the worker's publish lock, unless a clear() came
// in between). An empty function: nothing to publish.
class MapsSink {
 public:
  virtual ~MapsSink() = default;
  virtual std::function<void()> prepare(const MapsAssembler& maps, const MapsUpdateSummary& summary,
                                        const MapsJob& job) = 0;
};

struct MapsWorkerStats {
  // The last COMPLETED assembly (not the job of the update being reported: that one may still be
  // under way). Zero after clear() until the next one completes.
  MapsUpdateSummary last;
  long assemblingUpdates = 0;  // assemblies that wanted a map, since the worker started
  long completedJobs = 0;      // jobs assembled (and published unless cleared meanwhile)
  long coalescedJobs = 0;      // jobs merged into a pending one because the worker was busy
  long discardedJobs = 0;      // jobs dropped by clear() or assembled but not published after it
};

class MapsWorker {
 public:
  // The worker thread's nice value above its creator's: the maps are for viewing, the SLAM
  // update is the deadline. On 2 cores an assembly running flat out at the same priority took
  // CPU from the core's own threads (the sim robot's update median doubled); behind them it
  // only uses what they leave.
  static constexpr int kNiceIncrement = 10;

  // `sink` must outlive the worker; the thread starts here.
  explicit MapsWorker(MapsSink& sink, MapsAssembler assembler = MapsAssembler());
  ~MapsWorker();  // stop()
  MapsWorker(const MapsWorker&) = delete;
  MapsWorker& operator=(const MapsWorker&) = delete;

  // Queues `job` (merged into the pending one if any); returns at once.
  void submit(MapsJob job);
  // Drops the pending job and the maps (with `fresh`, the assembler is replaced: new options).
  // Waits only for a publish under way, so that nothing of the old maps follows this call.
  void clear(std::optional<MapsAssembler> fresh = std::nullopt);
  // Ends the thread: the assembly under way finishes unpublished, the pending job is dropped.
  // Idempotent; submit() after it does nothing.
  void stop();
  MapsWorkerStats stats() const;
  // Until nothing is pending nor under way (tests, benches): false on timeout.
  bool waitIdle(std::chrono::milliseconds timeout) const;

 private:
  void run();
  void assemble(MapsJob& job, std::uint64_t generation);
  // Under the publish lock: publishes unless the job's generation has passed. False if discarded.
  bool publishIfCurrent(const std::function<void()>& send, std::uint64_t generation);
  std::optional<rtabmap::LocalGrid> takeGrid(int nodeId);

  MapsSink& sink_;
  // Worker thread only.
  MapsAssembler assembler_;
  long earlierAssemblingUpdates_ = 0;  // of the assemblers replaced by clear(fresh)
  // Grids handed over and not yet taken by the assembler (kept while their node has no usable
  // pose, e.g. out of the optimised graph when the job ran).
  std::map<int, std::optional<rtabmap::LocalGrid>> handedGrids_;

  mutable std::mutex mutex_;  // what follows
  mutable std::condition_variable wake_, idle_;
  std::optional<MapsJob> pending_;
  bool clearPending_ = false;
  std::optional<MapsAssembler> freshAssembler_;
  bool busy_ = false;
  bool stopping_ = false;
  std::uint64_t generation_ = 0;  // + 1 at each clear() and at stop()
  MapsWorkerStats stats_;

  std::mutex publishMutex_;  // a publish vs clear(): see publishIfCurrent()
  std::thread thread_;       // last: starts once the rest is constructed
};

}  // namespace rtabmap_slam_node

#include "rtabmap_slam_node/MapsWorker.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <utility>

namespace rtabmap_slam_node {
namespace {

bool usablePose(const rtabmap::Transform& pose) { return !pose.isNull() && !pose.isInvalid(); }

// Linux: a thread's own nice value (PRIO_PROCESS with a thread id). Best effort: a failure
// leaves the thread at its creator's priority.
void lowerThisThreadPriority(int increment) {
  const id_t tid = static_cast<id_t>(::syscall(SYS_gettid));
  errno = 0;
  const int current = ::getpriority(PRIO_PROCESS, tid);
  if (errno == 0) ::setpriority(PRIO_PROCESS, tid, current + increment);
}

}  // namespace

void MapsJob::merge(MapsJob&& newer) {
  for (auto& [id, grid] : newer.grids) grids[id] = std::move(grid);  // the newer grid of a node wins
  invalidated.insert(newer.invalidated.begin(), newer.invalidated.end());
  poses = std::move(newer.poses);
  wanted = newer.wanted;
  force = force || newer.force;  // the new subscriber of the older job still waits for its maps
  frameId = std::move(newer.frameId);
  stampNs = newer.stampNs;
}

MapsWorker::MapsWorker(MapsSink& sink, MapsAssembler assembler)
    : sink_(sink), assembler_(std::move(assembler)), thread_([this] { run(); }) {}

MapsWorker::~MapsWorker() { stop(); }

void MapsWorker::submit(MapsJob job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return;
    if (pending_) {
      pending_->merge(std::move(job));
      ++stats_.coalescedJobs;
    } else {
      pending_ = std::move(job);
    }
  }
  wake_.notify_one();
}

void MapsWorker::clear(std::optional<MapsAssembler> fresh) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++generation_;
    if (pending_) ++stats_.discardedJobs;
    pending_.reset();
    clearPending_ = true;
    if (fresh) freshAssembler_ = std::move(fresh);
    stats_.last = MapsUpdateSummary();
  }
  wake_.notify_one();
  // A publish that checked the generation before the increment finishes before we return.
  std::lock_guard<std::mutex> published(publishMutex_);
}

void MapsWorker::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
    ++generation_;
    pending_.reset();
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

MapsWorkerStats MapsWorker::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

bool MapsWorker::waitIdle(std::chrono::milliseconds timeout) const {
  std::unique_lock<std::mutex> lock(mutex_);
  return idle_.wait_for(lock, timeout, [this] { return !busy_ && !pending_ && !clearPending_; });
}

void MapsWorker::run() {
  lowerThisThreadPriority(kNiceIncrement);
  for (;;) {
    std::optional<MapsJob> job;
    std::optional<MapsAssembler> fresh;
    bool clearFirst = false;
    std::uint64_t generation = 0;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || pending_ || clearPending_; });
      if (stopping_) break;
      job.swap(pending_);
      fresh.swap(freshAssembler_);
      clearFirst = std::exchange(clearPending_, false);
      generation = generation_;
      busy_ = true;
    }
    if (clearFirst) {
      if (fresh) {
        earlierAssemblingUpdates_ += assembler_.assemblingUpdates();
        assembler_ = std::move(*fresh);
      } else {
        assembler_.clear();
      }
      handedGrids_.clear();
    }
    if (job) assemble(*job, generation);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      busy_ = false;
    }
    idle_.notify_all();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  busy_ = false;
  idle_.notify_all();
}

std::optional<rtabmap::LocalGrid> MapsWorker::takeGrid(int nodeId) {
  auto it = handedGrids_.find(nodeId);
  if (it == handedGrids_.end()) return std::nullopt;
  std::optional<rtabmap::LocalGrid> grid = std::move(it->second);
  handedGrids_.erase(it);  // the assembler asks once for all its maps
  return grid;
}

void MapsWorker::assemble(MapsJob& job, std::uint64_t generation) {
  const auto start = std::chrono::steady_clock::now();
  for (int id : job.invalidated) assembler_.invalidate(id);
  for (auto& [id, grid] : job.grids) handedGrids_[id] = std::move(grid);
  MapsUpdateSummary summary = assembler_.update(job.poses, job.wanted, [this](int id) { return takeGrid(id); });
  // A grid of a posed node the assembler did not take is one every map already has. Only nodes
  // out of the graph keep theirs, and none when no map is wanted (the owner hands everything
  // again when one is).
  if (!job.wanted.any()) handedGrids_.clear();
  for (auto it = handedGrids_.begin(); it != handedGrids_.end();) {
    auto pose = job.poses.find(it->first);
    it = pose != job.poses.end() && usablePose(pose->second) ? handedGrids_.erase(it) : std::next(it);
  }
  const std::function<void()> send = job.wanted.any() ? sink_.prepare(assembler_, summary, job) : nullptr;
  const bool published = publishIfCurrent(send, generation);
  if (job.wanted.any()) {  // else nothing was done: 0, as MapsAssembler says
    // Assembling, making the messages and publishing them.
    summary.timeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.assemblingUpdates = earlierAssemblingUpdates_ + assembler_.assemblingUpdates();
  if (!published) {
    ++stats_.discardedJobs;
    return;
  }
  ++stats_.completedJobs;
  // A clear() right after the publish zeroed the figures: they stay so (not the old maps').
  if (generation == generation_) stats_.last = std::move(summary);
}

bool MapsWorker::publishIfCurrent(const std::function<void()>& send, std::uint64_t generation) {
  std::lock_guard<std::mutex> published(publishMutex_);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (generation != generation_) return false;
  }
  if (send) send();
  return true;
}

}  // namespace rtabmap_slam_node

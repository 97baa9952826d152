#include "Writer.h"

#include <chrono>

#include "NodeStore.h"
#include "Sqlite.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap::db {

namespace {
// Cap on small operations per transaction (links, updates...), so that a flood of them still
// commits regularly.
constexpr size_t kMaxBatchOperations = 4096;
}  // namespace

Writer::Writer(std::unique_ptr<Connection> connection, Config config)
    : connection_(std::move(connection)), config_(std::move(config)) {
  thread_ = std::thread([this] { run(); });
}

Writer::~Writer() { stop(); }

uint64_t Writer::push(std::shared_ptr<Operation> op, bool isNode) {
  retryIfDue();
  std::unique_lock<std::mutex> lock(mutex_);
  if (isNode && config_.maxPendingNodes > 0) {
    // Back-pressure: the disk cannot keep up; wait rather than grow without bound.
    progress_.wait(lock, [&] {
      return failed_ || stopping_ || queuedNodes_ < static_cast<size_t>(config_.maxPendingNodes);
    });
  }
  if (failed_) throw DatabaseError(failureMessage());
  if (stopping_) throw DatabaseError(connection_->path() + ": the database is closing; nothing more can be saved");
  op->ticket = ++lastTicket_;
  queue_.push_back(std::move(op));
  if (isNode) ++queuedNodes_;
  workAvailable_.notify_one();
  return lastTicket_;
}

void Writer::retryIfDue() {
  std::thread ended;
  std::string error;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!failed_ || stopping_) return;
    if (std::chrono::steady_clock::now() - failedAt_ < std::chrono::duration<double>(kRetrySeconds)) return;
    // The old thread returned right after failWith() (it may still be logging): joined below,
    // outside the lock, as a log sink may ask for the status.
    ended = std::move(thread_);
    failed_ = false;
    error.swap(error_);
    thread_ = std::thread([this] { run(); });
  }
  if (ended.joinable()) ended.join();
  RTABMAP_WARN("long-term memory: writing to " << connection_->path() << " again (after: " << error << ")");
}

void Writer::flush() {
  std::unique_lock<std::mutex> lock(mutex_);
  const uint64_t target = lastTicket_;
  progress_.wait(lock, [&] { return failed_ || durableTicket_ >= target; });
  if (durableTicket_ < target) throw DatabaseError(failureMessage());
}

void Writer::waitIdle() {
  std::unique_lock<std::mutex> lock(mutex_);
  progress_.wait(lock, [&] { return failed_ || queue_.empty(); });
}

void Writer::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  workAvailable_.notify_all();
  progress_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::vector<OperationPtr> Writer::pending() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::vector<OperationPtr>(queue_.begin(), queue_.end());
}

WriterStatus Writer::status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  WriterStatus s;
  s.failed = failed_;
  s.error = error_;
  s.lastDurableNodeId = lastDurableNodeId_;
  s.durableTicket = durableTicket_;
  s.queuedTicket = lastTicket_;
  s.pendingOperations = queue_.size();
  s.pendingNodes = queuedNodes_;
  return s;
}

std::string Writer::failureMessage() const {
  return "the long-term memory writer stopped after an error, " + std::to_string(queue_.size()) +
         " operations are not written (the last node saved is " +
         std::to_string(lastDurableNodeId_) + "): " + error_;
}

void Writer::run() {
  while (true) {
    const std::vector<OperationPtr> batch = nextBatch();
    if (batch.empty()) return;  // stopping and drained
    double seconds = 0.0;
    try {
      seconds = write(batch);
    } catch (const std::exception& e) {
      failWith(e.what());
      return;
    }
    finishBatch(batch, seconds);
  }
}

std::vector<OperationPtr> Writer::nextBatch() {
  std::unique_lock<std::mutex> lock(mutex_);
  workAvailable_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
  std::vector<OperationPtr> batch;
  int nodes = 0;
  for (const OperationPtr& op : queue_) {
    const bool node = std::holds_alternative<SaveNodeOp>(op->op);
    if (node && nodes == config_.maxBatchNodes) break;
    if (batch.size() == kMaxBatchOperations) break;
    nodes += node;
    batch.push_back(op);
  }
  return batch;
}

double Writer::write(const std::vector<OperationPtr>& batch) {
  const auto start = std::chrono::steady_clock::now();
  // One transaction for the batch: a node's rows (node, data, features, links, words) are
  // never split across transactions, and a crash leaves the whole batch out or in.
  Transaction transaction(*connection_);
  for (const OperationPtr& op : batch) store::apply(*connection_, *op, config_.imageFormat);
  transaction.commit();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Writer::finishBatch(const std::vector<OperationPtr>& batch, double writeSeconds) {
  CommitInfo commit;
  commit.ticket = batch.back()->ticket;
  commit.operations = batch.size();
  commit.writeSeconds = writeSeconds;
  // The batch stays at the head of the queue until acknowledged: only this thread removes it.
  for (const OperationPtr& op : batch) {
    if (const auto* save = std::get_if<SaveNodeOp>(&op->op)) commit.nodeIds.push_back(save->node.id());
  }
  // Acknowledge before releasing flush() waiters, so a caller returning from flush() has also
  // been told about every node it covers. Outside the lock: the callback may ask for status.
  if (config_.onCommitted) {
    try {
      config_.onCommitted(commit);
    } catch (const std::exception& e) {
      RTABMAP_ERROR("long-term memory: the onCommitted callback threw: " << e.what());
    }
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queuedNodes_ -= commit.nodeIds.size();
    queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(batch.size()));
    durableTicket_ = commit.ticket;
    if (!commit.nodeIds.empty()) lastDurableNodeId_ = commit.nodeIds.back();
  }
  progress_.notify_all();
}

void Writer::failWith(const std::string& error) {
  std::string message;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    failed_ = true;
    failedAt_ = std::chrono::steady_clock::now();
    error_ = error;
    message = failureMessage();
  }
  progress_.notify_all();
  RTABMAP_ERROR(message);  // outside the lock: a log sink may well ask for the status
}

}  // namespace rtabmap::db

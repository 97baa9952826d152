#pragma once
// The background writer (the "trash" thread of T-RO 2013, section 3.2: nodes transferred to
// the LTM are written by another thread so the real-time update never waits on the disk).
//
// Operations wait in one ordered queue. The thread takes the head of the queue (up to
// maxBatchNodes nodes and whatever small operations lie between them), writes it in one
// transaction, commits, and only then removes it from the queue: an operation is always
// either still queued (readers see it there) or committed (readers see it in the file).
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "Operations.h"
#include "rtabmap_core/db/Types.h"

namespace rtabmap::db {

class Connection;

class Writer {
 public:
  struct Config {
    int maxBatchNodes = 32;
    int maxPendingNodes = 1000;  // 0: unbounded
    std::string imageFormat = ".jpg";
    std::function<void(const CommitInfo& commit)> onCommitted;
  };

  // Takes the connection (schema ready) and starts the thread.
  Writer(std::unique_ptr<Connection> connection, Config config);
  // Stops (draining the queue) and closes the connection.
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // Queues an operation and returns its ticket. Blocks while maxPendingNodes nodes are queued.
  // Throws DatabaseError once the writer has failed, until kRetrySeconds after the failure:
  // then the writer starts again with what is queued (the failed batch first; its transaction
  // was rolled back), so that space freed on a full disk is used again.
  template <typename Op>
  uint64_t enqueue(Op op) {
    return push(std::make_shared<Operation>(Operation{0, std::move(op)}), isNode(op));
  }
  // Waits until everything queued so far is committed; throws DatabaseError if it cannot be.
  void flush();
  // Waits until the queue is empty or the writer failed; never throws.
  void waitIdle();
  // Writes what is queued, then ends the thread (idempotent). The connection stays open
  // until destruction.
  void stop();

  // The queued operations (including the batch being written), oldest first.
  std::vector<OperationPtr> pending() const;
  WriterStatus status() const;

 private:
  static bool isNode(const SaveNodeOp&) { return true; }
  template <typename Op>
  static bool isNode(const Op&) { return false; }

  static constexpr double kRetrySeconds = 5.0;

  uint64_t push(std::shared_ptr<Operation> op, bool isNode);
  // After a failure: starts the thread again once kRetrySeconds passed (takes mutex_).
  void retryIfDue();
  void run();
  // Takes the next batch from the head of the queue (without removing it).
  std::vector<OperationPtr> nextBatch();
  // Writes and commits the batch; returns the seconds it took.
  double write(const std::vector<OperationPtr>& batch);
  void finishBatch(const std::vector<OperationPtr>& batch, double writeSeconds);
  void failWith(const std::string& error);
  std::string failureMessage() const;  // with mutex_ held

  std::unique_ptr<Connection> connection_;
  const Config config_;

  mutable std::mutex mutex_;
  std::condition_variable workAvailable_;  // signalled on push and stop
  std::condition_variable progress_;       // signalled on commit and failure
  std::deque<OperationPtr> queue_;
  size_t queuedNodes_ = 0;
  uint64_t lastTicket_ = 0;
  uint64_t durableTicket_ = 0;
  int lastDurableNodeId_ = 0;
  bool stopping_ = false;
  bool failed_ = false;
  std::chrono::steady_clock::time_point failedAt_;
  std::string error_;
  std::thread thread_;
};

}  // namespace rtabmap::db

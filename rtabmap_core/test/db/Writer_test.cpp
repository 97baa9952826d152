// The asynchronous writer: saving does not wait for the disk, flush() does, commits come in
// order, and loads made while the writer writes always see complete nodes.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

#include "common/TestData.h"
#include "db/DbTestUtil.h"
#include "rtabmap_core/db/Database.h"

namespace rtabmap::test::db {
namespace {

using rtabmap::db::Database;
using rtabmap::db::LoadOptions;

TEST(DatabaseWriter, FlushWaitsForEverythingQueued) {
  TempDir dir;
  std::vector<int> durable;
  std::mutex mutex;
  Database::Options options;
  options.maxBatchNodes = 4;
  uint64_t lastTicket = 0;
  bool ticketsIncrease = true;
  options.onCommitted = [&](const rtabmap::db::CommitInfo& commit) {
    std::lock_guard<std::mutex> lock(mutex);
    durable.insert(durable.end(), commit.nodeIds.begin(), commit.nodeIds.end());
    ticketsIncrease &= commit.ticket > lastTicket && commit.writeSeconds > 0.0 && commit.nodeIds.size() <= 4;
    lastTicket = commit.ticket;
  };
  Database db(dir.file("ltm.db"), options);
  uint64_t ticket = 0;
  for (int id = 1; id <= 60; ++id) ticket = db.saveNode(makeNode(id, 0, 20), wordsOf(id, 20));
  db.flush();
  const rtabmap::db::WriterStatus status = db.writerStatus();
  EXPECT_EQ(0u, status.pendingOperations);
  EXPECT_EQ(0u, status.pendingNodes);
  EXPECT_EQ(ticket, status.durableTicket);
  EXPECT_EQ(60, status.lastDurableNodeId);
  EXPECT_EQ(60, db.lastDurableNodeId());
  EXPECT_FALSE(status.failed);
  {
    // Every node acknowledged once, in the order saved.
    std::lock_guard<std::mutex> lock(mutex);
    EXPECT_TRUE(ticketsIncrease);  // in order, timed, at most maxBatchNodes nodes each
    EXPECT_EQ(ticket, lastTicket);
    ASSERT_EQ(60u, durable.size());
    for (int i = 0; i < 60; ++i) EXPECT_EQ(i + 1, durable[i]);
  }
  // What flush() promised is in the file: a second, independent connection sees it all.
  Database::Options readOnly;
  readOnly.readOnly = true;
  Database other(dir.file("ltm.db"), readOnly);
  EXPECT_EQ(60u, other.nodeIds().size());
  expectSameNode(makeNode(60, 0, 20), *other.loadNode(60));
}

TEST(DatabaseWriter, LaterSaveOfTheSameNodeWins) {
  TempDir dir;
  Database db(dir.file("ltm.db"));
  for (int round = 0; round < 5; ++round) {
    Signature node = makeNode(1, 0, 10);
    node.setWeight(round);
    db.saveNode(node);
    EXPECT_EQ(round, db.loadNode(1)->weight());  // queued or written, the latest
  }
  db.flush();
  EXPECT_EQ(4, db.loadNode(1)->weight());
  EXPECT_EQ(1u, db.nodeIds().size());
}

TEST(DatabaseWriter, SavingDoesNotWaitForTheDisk) {
  TempDir dir;
  Database::Options options;
  options.synchronous = Database::Options::Synchronous::kFull;  // an fsync per commit
  options.maxBatchNodes = 1;
  Database db(dir.file("ltm.db"), options);
  std::vector<Signature> nodes;
  for (int id = 1; id <= 100; ++id) nodes.push_back(makeNode(id, 0, 200));
  const auto start = std::chrono::steady_clock::now();
  for (Signature& node : nodes) db.saveNode(std::move(node));
  const double enqueueMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const size_t pendingAfterEnqueue = db.writerStatus().pendingNodes;
  const auto flushStart = std::chrono::steady_clock::now();
  db.flush();
  const double flushMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - flushStart).count();
  // The caller only queued: the writer was still busy when save() returned for the last one.
  EXPECT_GT(pendingAfterEnqueue, 0u) << "enqueue took " << enqueueMs << " ms, flush " << flushMs << " ms";
  EXPECT_EQ(100, db.lastDurableNodeId());
}

TEST(DatabaseWriter, BackPressureBoundsTheQueue) {
  TempDir dir;
  Database::Options options;
  options.maxPendingNodes = 3;
  options.maxBatchNodes = 1;
  size_t maxPending = 0;
  Database db(dir.file("ltm.db"), options);
  for (int id = 1; id <= 40; ++id) {
    db.saveNode(makeNode(id, 0, 50));
    maxPending = std::max(maxPending, db.writerStatus().pendingNodes);
  }
  EXPECT_LE(maxPending, 3u);
  db.flush();
  EXPECT_EQ(40u, db.nodeIds().size());
}

TEST(DatabaseWriter, LoadsDuringWritesAreConsistent) {
  TempDir dir;
  Database::Options options;
  options.maxBatchNodes = 3;
  Database db(dir.file("ltm.db"), options);
  constexpr int kNodes = 150;
  std::atomic<int> saved{0};
  std::atomic<bool> done{false};
  std::atomic<int> checks{0};
  std::atomic<int> failures{0};
  // Readers load nodes already handed to save() while the writer is writing them: each load
  // must return the whole node (never a node without its words, links or data).
  auto reader = [&](unsigned seed) {
    std::mt19937 rng(seed);
    while (!done) {
      const int available = saved.load();
      if (available == 0) continue;
      const int id = 1 + static_cast<int>(rng() % available);
      const std::optional<Signature> node = db.loadNode(id);
      if (!node) {
        ++failures;
        continue;
      }
      const Signature expected = makeNode(id, 0, 30);
      const bool same = node->getWords() == expected.getWords() &&
                        node->getLinks().size() == expected.getLinks().size() &&
                        sameMat(node->getWordsDescriptors(), expected.getWordsDescriptors()) &&
                        node->sensorData().imageCompressed() == expected.sensorData().imageCompressed() &&
                        sameMat(node->sensorData().localGrid().ground, expected.sensorData().localGrid().ground);
      if (!same) ++failures;
      const std::map<int, int> around = db.neighborIds(id, 1);
      if (!around.count(id) || (id > 1 && !around.count(id - 1))) ++failures;
      ++checks;
    }
  };
  std::thread r1(reader, 1), r2(reader, 2);
  for (int id = 1; id <= kNodes; ++id) {
    db.saveNode(makeNode(id, 0, 30), wordsOf(id, 30));
    saved = id;
    if (id % 10 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  db.flush();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  done = true;
  r1.join();
  r2.join();
  EXPECT_EQ(0, failures.load());
  EXPECT_GT(checks.load(), 50);
  EXPECT_EQ(static_cast<size_t>(kNodes), db.nodeIds().size());
  EXPECT_TRUE(db.checkConsistency(true).ok());
}

// A write failure that goes away (space freed on a full disk; here another process holding the
// file locked longer than busyTimeoutMs): saves are refused at first, then the writer starts
// again with what was queued, and nothing queued or saved after is lost.
TEST(DatabaseWriter, StartsAgainAfterATransientFailure) {
  TempDir dir;
  const std::string path = dir.file("transient.db");
  Database::Options options;
  options.busyTimeoutMs = 100;
  Database db(path, options);
  db.saveNode(makeNode(1, 0));
  db.flush();
  {
    RawSqlite other(path);
    other.exec("BEGIN EXCLUSIVE");
    db.saveNode(makeNode(2, 0));
    EXPECT_NE(std::string::npos, errorOf([&] { db.flush(); }).find("locked")) << "the lock did not fail the writer";
    EXPECT_TRUE(db.writerStatus().failed);
    EXPECT_FALSE(errorOf([&] { db.saveNode(makeNode(3, 0)); }).empty());  // refused at once
    other.exec("COMMIT");
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(5200));  // Writer::kRetrySeconds
  EXPECT_TRUE(errorOf([&] { db.saveNode(makeNode(4, 0)); }).empty());
  EXPECT_TRUE(errorOf([&] { db.flush(); }).empty());
  EXPECT_FALSE(db.writerStatus().failed);
  EXPECT_EQ(4, db.lastDurableNodeId());
  for (int id : {1, 2, 4}) EXPECT_TRUE(db.loadNode(id).has_value()) << id;
  EXPECT_FALSE(db.loadNode(3).has_value());  // refused: its owner keeps it (Memory does)
}

}  // namespace
}  // namespace rtabmap::test::db

// Crash safety: a child process writes nodes and reports each one the writer acknowledged as
// durable; the parent kills it with SIGKILL mid-stream, reopens the database, and finds every
// acknowledged node complete and no partial node at all.
//
// The child is this test binary itself, re-executed with a gtest filter selecting
// DatabaseKillChild.WritesUntilKilled and the database path and pipe in its environment
// (exec rather than a bare fork: the parent may hold threads, e.g. OpenCV's pool, that a
// forked child would not have).
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <set>
#include <string>
#include <thread>

#include "common/TestData.h"
#include "db/DbTestUtil.h"
#include "rtabmap_core/db/Database.h"

extern char** environ;

namespace rtabmap::test::db {
namespace {

using rtabmap::db::Database;

constexpr int kWords = 40;
// The child prepares this many nodes, then queues them all at once so that the writer is
// busy (mid-transaction) at any moment the kill lands; it is killed before it gets to the end.
constexpr int kMaxNodes = 1500;
constexpr const char* kPathVar = "RTABMAP_DB_KILL_CHILD_PATH";
constexpr const char* kFdVar = "RTABMAP_DB_KILL_CHILD_FD";

// Runs only as the child of KillTest (the variables are set); in a normal run it has nothing
// to do and passes.
TEST(DatabaseKillChild, WritesUntilKilled) {
  const char* path = std::getenv(kPathVar);
  const char* fdText = std::getenv(kFdVar);
  if (!path || !fdText) return;
  const int fd = std::atoi(fdText);
  Database::Options options;
  options.maxBatchNodes = 8;
  options.onCommitted = [fd](const rtabmap::db::CommitInfo& commit) {
    // Acknowledge on the writer thread, right after the commit: exactly what is safe.
    for (int id : commit.nodeIds) {
      const std::string line = std::to_string(id) + "\n";
      if (::write(fd, line.data(), line.size()) < 0) std::_Exit(3);
    }
  };
  options.maxPendingNodes = 0;
  std::vector<Signature> nodes;
  for (int id = 1; id <= kMaxNodes; ++id) nodes.push_back(makeNode(id, 0, kWords));
  Database db(path, options);
  for (Signature& node : nodes) {
    const int id = node.id();
    db.saveNode(std::move(node), wordsOf(id, kWords));
  }
  db.flush();
  std::_Exit(2);  // killed too late: the parent reports it
}

struct ChildRun {
  std::set<int> acknowledged;
  int killedAfter = 0;
  bool killedBySignal = false;
  std::string status;
};

// Starts the child, kills it after `killAfter` acknowledgements, collects all of them.
ChildRun runAndKill(const std::string& dbPath, int killAfter) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error("pipe failed");
  // Everything exec needs is prepared before fork: between fork and exec the child may only
  // make async-signal-safe calls.
  const std::string exe = "/proc/self/exe";
  const std::string filter = "--gtest_filter=DatabaseKillChild.WritesUntilKilled";
  const std::string pathVar = std::string(kPathVar) + "=" + dbPath;
  const std::string fdVar = std::string(kFdVar) + "=" + std::to_string(fds[1]);
  std::vector<char*> argv{const_cast<char*>(exe.c_str()), const_cast<char*>(filter.c_str()), nullptr};
  std::vector<char*> envp;
  for (char** e = environ; *e; ++e) envp.push_back(*e);
  envp.push_back(const_cast<char*>(pathVar.c_str()));
  envp.push_back(const_cast<char*>(fdVar.c_str()));
  envp.push_back(nullptr);

  const pid_t child = ::fork();
  if (child < 0) throw std::runtime_error("fork failed");
  if (child == 0) {
    ::close(fds[0]);
    ::execve(exe.c_str(), argv.data(), envp.data());
    ::_exit(127);
  }
  ::close(fds[1]);

  ChildRun run;
  std::string buffer;
  char chunk[4096];
  bool killed = false;
  while (true) {
    const ssize_t n = ::read(fds[0], chunk, sizeof(chunk));
    if (n <= 0) break;  // EOF: the child is gone and everything it wrote has been read
    buffer.append(chunk, static_cast<size_t>(n));
    size_t newline;
    while ((newline = buffer.find('\n')) != std::string::npos) {
      run.acknowledged.insert(std::stoi(buffer.substr(0, newline)));
      buffer.erase(0, newline + 1);
    }
    if (!killed && static_cast<int>(run.acknowledged.size()) >= killAfter) {
      // A little later than the acknowledgement, so the kill does not always land just
      // after a commit.
      std::this_thread::sleep_for(std::chrono::microseconds(killAfter * 7 % 1500));
      ::kill(child, SIGKILL);
      killed = true;
      run.killedAfter = static_cast<int>(run.acknowledged.size());
    }
  }
  ::close(fds[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  run.killedBySignal = WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
  run.status = WIFEXITED(status) ? "exited with code " + std::to_string(WEXITSTATUS(status))
                                 : "signal " + std::to_string(WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  return run;
}

TEST(DatabaseKill, AcknowledgedNodesSurviveSigkillAndNoNodeIsPartial) {
  // Kill points: a few hundred acknowledgements, shifted by a clock-dependent amount so that
  // runs hit different moments of the writer's cycle (mid-transaction, mid-checkpoint...).
  const unsigned jitter = static_cast<unsigned>(std::chrono::steady_clock::now().time_since_epoch().count());
  for (int base : {150, 400, 700}) {
    const int killAfter = base + static_cast<int>(jitter % 97);
    SCOPED_TRACE("kill after " + std::to_string(killAfter) + " acknowledged nodes");
    TempDir dir;
    const std::string path = dir.file("ltm.db");
    const ChildRun run = runAndKill(path, killAfter);
    ASSERT_TRUE(run.killedBySignal) << "the child was not killed by SIGKILL: " << run.status;
    ASSERT_GE(static_cast<int>(run.acknowledged.size()), killAfter);
    const int lastAcknowledged = *run.acknowledged.rbegin();
    // Acknowledgements come in save order, without gaps.
    EXPECT_EQ(static_cast<int>(run.acknowledged.size()), lastAcknowledged);

    // Reopen as a restarted robot would (recovering the WAL), and check.
    Database db(path);
    const std::vector<int> ids = db.nodeIds();
    ASSERT_GE(static_cast<int>(ids.size()), lastAcknowledged) << "acknowledged nodes are missing";
    for (size_t i = 0; i < ids.size(); ++i) ASSERT_EQ(static_cast<int>(i) + 1, ids[i]) << "a gap in the saved nodes";
    // Every node in the file, acknowledged or committed just before the kill, is complete
    // and exactly what was saved.
    for (int id : ids) {
      const std::optional<Signature> node = db.loadNode(id);
      ASSERT_TRUE(node);
      expectSameNode(makeNode(id, 0, kWords), *node);
      std::vector<int> wordIds = node->wordIdPerKeypoint();
      std::sort(wordIds.begin(), wordIds.end());
      wordIds.erase(std::unique(wordIds.begin(), wordIds.end()), wordIds.end());
      ASSERT_EQ(wordIds.size(), db.loadWords(wordIds).size()) << "words of node " << id << " are missing";
      if (::testing::Test::HasFailure()) return;
    }
    // No partial node: every node row has its data and features, no orphan rows, every word
    // referenced exists, and SQLite finds the file sound.
    const rtabmap::db::ConsistencyReport report = db.checkConsistency(true);
    EXPECT_TRUE(report.ok()) << report.toString();
    EXPECT_EQ(0, report.missingWords) << report.toString();
    std::cout << "[ kill ] killed after " << run.killedAfter << " acks; " << run.acknowledged.size()
              << " acknowledged, " << ids.size() << " in the file after recovery" << std::endl;
  }
}

}  // namespace
}  // namespace rtabmap::test::db

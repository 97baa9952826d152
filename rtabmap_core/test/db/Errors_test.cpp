// The long-term memory refuses what it cannot use, with a message that says what and why:
// newer schema, corrupt or foreign files, permissions, missing directories, a full disk.
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <mutex>

#include "common/TestData.h"
#include "db/DbTestUtil.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/db/Database.h"

namespace rtabmap::test::db {
namespace {

using rtabmap::db::Database;

Database::Options readOnly() {
  Database::Options o;
  o.readOnly = true;
  return o;
}

// A closed database of `nodes` nodes.
void makeDatabase(const std::string& path, int nodes, int words = 30) {
  Database db(path);
  for (int id = 1; id <= nodes; ++id) db.saveNode(makeNode(id, 0, words), wordsOf(id, words));
  db.close();
}

TEST(DatabaseErrors, NewerSchemaVersionIsRefused) {
  TempDir dir;
  const std::string path = dir.file("newer.db");
  makeDatabase(path, 3);
  {
    RawSqlite raw(path);
    raw.exec("PRAGMA user_version = 7; UPDATE Admin SET schema_version = 7, written_by = '9.9.9'");
  }
  const std::string expected = "database version 7 was written by a newer rtabmap_ros (9.9.9); this build reads up to " +
                               std::to_string(rtabmap::db::kSchemaVersion);
  for (const Database::Options& options : {Database::Options(), readOnly()}) {
    Database db;
    const std::string error = errorOf([&] { db.open(path, options); });
    EXPECT_NE(std::string::npos, error.find(expected)) << error;
    EXPECT_NE(std::string::npos, error.find(path)) << error;
    EXPECT_FALSE(db.isOpen());
  }
}

TEST(DatabaseErrors, NewerSchemaWithAnotherAdminLayoutIsStillExplained) {
  TempDir dir;
  const std::string path = dir.file("newer.db");
  makeDatabase(path, 1);
  {
    RawSqlite raw(path);
    raw.exec("PRAGMA user_version = 8; ALTER TABLE Admin RENAME COLUMN written_by TO writer");
  }
  const std::string error = errorOf([&] { Database db(path); });
  EXPECT_NE(std::string::npos, error.find("database version 8 was written by a newer rtabmap_ros (an unknown version)"))
      << error;
}

TEST(DatabaseErrors, RandomBytesAreNotADatabase) {
  TempDir dir;
  const std::string path = dir.file("random.db");
  std::vector<char> bytes(8192);
  std::mt19937 rng(drawSeed(3));
  for (char& b : bytes) b = static_cast<char>(rng());
  writeFile(path, bytes);
  for (const Database::Options& options : {Database::Options(), readOnly()}) {
    const std::string error = errorOf([&] { Database db(path, options); });
    EXPECT_NE(std::string::npos, error.find(path)) << error;
    EXPECT_NE(std::string::npos, error.find("not an SQLite database")) << error;
  }
  // The file is left as it was.
  EXPECT_EQ(bytes, readFile(path));
}

TEST(DatabaseErrors, GarbageAfterAValidHeaderIsCorrupt) {
  TempDir dir;
  const std::string path = dir.file("garbage.db");
  makeDatabase(path, 3);
  std::vector<char> bytes = readFile(path);
  std::mt19937 rng(drawSeed(5));
  for (size_t i = 100; i < bytes.size(); ++i) bytes[i] = static_cast<char>(rng());  // keep the header
  writeFile(path, bytes);
  const std::string error = errorOf([&] { Database db(path, readOnly()); });
  EXPECT_NE(std::string::npos, error.find(path)) << error;
  EXPECT_NE(std::string::npos, error.find("corrupt")) << error;
}

TEST(DatabaseErrors, TruncatedCopyIsRefused) {
  TempDir dir;
  const std::string path = dir.file("full.db");
  makeDatabase(path, 40);
  const std::vector<char> bytes = readFile(path);
  ASSERT_GT(bytes.size(), 20000u);
  const std::string truncated = dir.file("truncated.db");
  writeFile(truncated, std::vector<char>(bytes.begin(), bytes.begin() + bytes.size() / 2));
  for (const Database::Options& options : {Database::Options(), readOnly()}) {
    const std::string error = errorOf([&] { Database db(truncated, options); });
    EXPECT_NE(std::string::npos, error.find(truncated)) << error;
    EXPECT_NE(std::string::npos, error.find("truncated")) << error;
  }
  // Cut inside the header too.
  writeFile(truncated, std::vector<char>(bytes.begin(), bytes.begin() + 50));
  const std::string error = errorOf([&] { Database db(truncated, readOnly()); });
  EXPECT_NE(std::string::npos, error.find("truncated")) << error;
}

// Found through the node (test/fault_database.test): a dropped table was only noticed when a
// load needed it, after opening for writing had already added a session to the file.
TEST(DatabaseErrors, MissingTableIsRefusedBeforeAnyWrite) {
  TempDir dir;
  const std::string path = dir.file("dropped.db");
  makeDatabase(path, 3);
  {
    RawSqlite raw(path);
    raw.exec("DROP TABLE Link; DROP TABLE Word");
  }
  const std::vector<char> before = readFile(path);
  const bool walBefore = std::filesystem::exists(path + "-wal");
  for (const Database::Options& options : {Database::Options(), readOnly()}) {
    Database db;
    const std::string error = errorOf([&] { db.open(path, options); });
    EXPECT_NE(std::string::npos, error.find("database " + path + " is damaged: table(s) Word, Link of schema version"))
        << error;
    EXPECT_FALSE(db.isOpen());
    EXPECT_EQ(before, readFile(path));
    // (A read-only SQLite connection to a WAL file leaves an empty -wal and -shm behind.)
    if (!options.readOnly) {
      EXPECT_EQ(walBefore, std::filesystem::exists(path + "-wal"));
    }
  }
}

TEST(DatabaseErrors, ForeignSqliteDatabaseIsRefused) {
  TempDir dir;
  const std::string path = dir.file("foreign.db");
  {
    RawSqlite raw(path);
    raw.exec("CREATE TABLE cars (name TEXT); CREATE TABLE owners (id INTEGER); INSERT INTO cars VALUES ('a')");
  }
  const std::vector<char> before = readFile(path);
  for (const Database::Options& options : {Database::Options(), readOnly()}) {
    const std::string error = errorOf([&] { Database db(path, options); });
    EXPECT_NE(std::string::npos, error.find(path)) << error;
    EXPECT_NE(std::string::npos, error.find("not an rtabmap_ros long-term memory")) << error;
    EXPECT_NE(std::string::npos, error.find("cars, owners")) << error;
  }
  EXPECT_EQ(before, readFile(path));  // untouched: no table added, no session written
}

TEST(DatabaseErrors, MissingDirectoryAndFile) {
  TempDir dir;
  const std::string inMissingDir = dir.file("no/such/dir/ltm.db");
  std::string error = errorOf([&] { Database db(inMissingDir); });
  EXPECT_NE(std::string::npos, error.find("directory " + dir.file("no/such/dir") + " does not exist")) << error;
  EXPECT_FALSE(std::filesystem::exists(dir.file("no")));

  error = errorOf([&] { Database db(dir.file("missing.db"), readOnly()); });
  EXPECT_NE(std::string::npos, error.find(dir.file("missing.db") + ": the file does not exist")) << error;
  EXPECT_FALSE(std::filesystem::exists(dir.file("missing.db")));

  Database::Options noCreate;
  noCreate.createIfMissing = false;
  error = errorOf([&] { Database db(dir.file("missing.db"), noCreate); });
  EXPECT_NE(std::string::npos, error.find("does not exist")) << error;

  error = errorOf([&] { Database db(dir.path()); });
  EXPECT_NE(std::string::npos, error.find("it is a directory")) << error;
}

TEST(DatabaseErrors, ReadOnlyOpenModeReadsAndRefusesWrites) {
  TempDir dir;
  const std::string path = dir.file("ltm.db");
  makeDatabase(path, 5);
  const std::vector<char> before = readFile(path);
  {
    Database db(path, readOnly());
    EXPECT_TRUE(db.isReadOnly());
    EXPECT_EQ(-1, db.sessionMapId());
    expectSameNode(makeNode(5, 0, 30), *db.loadNode(5));
    const std::string error = errorOf([&] { db.saveNode(makeNode(6, 0, 3)); });
    EXPECT_NE(std::string::npos, error.find(path + ": opened read-only; nothing can be saved")) << error;
    EXPECT_FALSE(errorOf([&] { db.saveLink(Link(1, 2, Link::kUserClosure, Transform::Identity())); }).empty());
    EXPECT_NO_THROW(db.flush());
    EXPECT_EQ(1u, db.sessions().size());  // no session added
  }
  EXPECT_EQ(before, readFile(path));
}

TEST(DatabaseErrors, EmptyFileReadOnlyIsReported) {
  TempDir dir;
  const std::string path = dir.file("empty.db");
  writeFile(path, {});
  const std::string error = errorOf([&] { Database db(path, readOnly()); });
  EXPECT_NE(std::string::npos, error.find("is empty")) << error;
  // For writing, an empty file is a new database.
  Database db(path);
  EXPECT_TRUE(db.isOpen());
}

// chmod cannot stop root (the tests usually run as root in containers): then the write
// permission checks cannot be exercised, and the test says so.
bool permissionsApply(const std::string& path) { return ::access(path.c_str(), W_OK) != 0; }

TEST(DatabaseErrors, ReadOnlyFileOpensOnlyForReading) {
  TempDir dir;
  const std::string path = dir.file("ltm.db");
  makeDatabase(path, 3);
  ASSERT_EQ(0, ::chmod(path.c_str(), 0444));
  if (!permissionsApply(path)) {
    GTEST_SKIP() << "running as root (uid " << ::geteuid() << "): chmod 0444 does not stop this process "
                 << "from writing, so the read-only-file check cannot be exercised; the read-only open mode "
                 << "is tested by ReadOnlyOpenModeReadsAndRefusesWrites";
  }
  const std::string error = errorOf([&] { Database db(path); });
  EXPECT_NE(std::string::npos, error.find(path)) << error;
  EXPECT_NE(std::string::npos, error.find("the file is read-only")) << error;
  Database db(path, readOnly());
  EXPECT_EQ(3u, db.nodeIds().size());
}

TEST(DatabaseErrors, ReadOnlyDirectoryOpensOnlyForReading) {
  TempDir dir;
  const std::string sub = dir.file("ro");
  std::filesystem::create_directory(sub);
  const std::string path = sub + "/ltm.db";
  makeDatabase(path, 3);
  ASSERT_EQ(0, ::chmod(sub.c_str(), 0555));
  struct Restore {
    std::string dir;
    ~Restore() { ::chmod(dir.c_str(), 0755); }  // so TempDir can remove it
  } restore{sub};
  if (!permissionsApply(sub)) {
    GTEST_SKIP() << "running as root (uid " << ::geteuid() << "): chmod 0555 does not stop this process "
                 << "from writing in the directory, so the read-only-directory check cannot be exercised";
  }
  std::string error = errorOf([&] { Database db(path); });
  EXPECT_NE(std::string::npos, error.find("directory " + sub + " is not writable")) << error;
  error = errorOf([&] { Database db(sub + "/new.db"); });
  EXPECT_NE(std::string::npos, error.find("is not writable")) << error;
  Database db(path, readOnly());  // a cleanly closed WAL database is read in immutable mode
  EXPECT_EQ(3u, db.nodeIds().size());
}

TEST(DatabaseErrors, FullDiskStopsTheWriterAndKeepsCommittedNodes) {
  TempDir dir;
  const std::string path = dir.file("full.db");
  std::vector<std::string> logged;
  std::mutex logMutex;
  setLogSink([&](LogLevel level, const std::string& message) {
    std::lock_guard<std::mutex> lock(logMutex);
    if (level >= LogLevel::kError) logged.push_back(message);
  });
  int lastDurable = 0;
  {
    Database::Options options;
    options.maxPageCount = 40;  // 160 KiB with 4 KiB pages: a "disk" that fills after a few nodes
    options.maxBatchNodes = 1;
    Database db(path, options);
    int id = 1;
    std::string saveError;
    for (; id <= 500 && saveError.empty(); ++id) {
      saveError = errorOf([&] { db.saveNode(makeNode(id, 0, 50), wordsOf(id, 50)); });
      if (saveError.empty()) saveError = errorOf([&] { db.flush(); });
    }
    ASSERT_FALSE(saveError.empty()) << "the page limit was never reached";
    EXPECT_NE(std::string::npos, saveError.find("disk is full")) << saveError;
    const rtabmap::db::WriterStatus status = db.writerStatus();
    EXPECT_TRUE(status.failed);
    EXPECT_NE(std::string::npos, status.error.find("SQLITE_FULL")) << status.error;
    lastDurable = status.lastDurableNodeId;
    EXPECT_GT(lastDurable, 0);
    // Later saves fail at once with the same cause.
    EXPECT_NE(std::string::npos, errorOf([&] { db.saveNode(makeNode(999, 0, 5)); }).find("disk is full"));
    // The node that did not fit is still readable from the queue.
    EXPECT_TRUE(db.loadNode(lastDurable + 1));
    const std::string closeError = errorOf([&] { db.close(); });
    EXPECT_NE(std::string::npos, closeError.find("operations not written")) << closeError;
  }
  setLogSink([](LogLevel level, const std::string& message) {
    if (level >= LogLevel::kWarning) std::cerr << "[" << logLevelName(level) << "] " << message << std::endl;
  });
  ASSERT_FALSE(logged.empty());
  EXPECT_NE(std::string::npos, logged.front().find("disk is full")) << logged.front();

  // Reopened: every committed node is there and intact, nothing else, and the file is sound.
  Database db(path, readOnly());
  const std::vector<int> ids = db.nodeIds();
  ASSERT_EQ(static_cast<size_t>(lastDurable), ids.size());
  for (int id = 1; id <= lastDurable; ++id) expectSameNode(makeNode(id, 0, 50), *db.loadNode(id));
  const auto report = db.checkConsistency(true);
  EXPECT_TRUE(report.ok()) << report.toString();
}

}  // namespace
}  // namespace rtabmap::test::db

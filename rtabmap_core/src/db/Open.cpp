#include "Open.h"

#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <filesystem>

#include "FileChecks.h"
#include "Sqlite.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap::db::open {

namespace {

const char* journalModeName(Database::Options::JournalMode mode) {
  using M = Database::Options::JournalMode;
  switch (mode) {
    case M::kDelete: return "DELETE";
    case M::kTruncate: return "TRUNCATE";
    case M::kPersist: return "PERSIST";
    case M::kMemory: return "MEMORY";
    case M::kOff: return "OFF";
    case M::kWal: return "WAL";
  }
  return "WAL";
}

// PRAGMA values cannot be bound parameters; every value here is one of our integers or one of
// the fixed names above, never user text.
void commonPragmas(Connection& c, const Database::Options& o) {
  c.exec("PRAGMA busy_timeout = " + std::to_string(o.busyTimeoutMs));
  c.exec("PRAGMA cache_size = " + std::to_string(o.cacheSize));
  c.exec("PRAGMA temp_store = " + std::to_string(o.tempStore));
}

void writerPragmas(Connection& c, const Database::Options& o) {
  commonPragmas(c, o);
  const std::string wanted = journalModeName(o.journalMode);
  std::string mode;
  {
    Query q = c.query(std::string("PRAGMA journal_mode = ") + wanted);
    if (q->step()) mode = q->columnText(0);
  }
  for (char& ch : mode) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  if (mode != wanted) {
    RTABMAP_WARN("database " << c.path() << ": journal mode " << wanted << " refused, using " << mode
                             << (o.journalMode == Database::Options::JournalMode::kWal
                                     ? " (loads will wait for the writer's transactions)"
                                     : ""));
  }
  c.exec("PRAGMA synchronous = " + std::to_string(static_cast<int>(o.synchronous)));
  if (o.maxPageCount > 0) c.exec("PRAGMA max_page_count = " + std::to_string(o.maxPageCount));
}

// "file:" URI of a path, percent-encoding what URIs reserve.
std::string fileUri(const std::string& path, const std::string& query) {
  std::string uri = "file:";
  for (unsigned char ch : std::filesystem::absolute(path).string()) {
    if (std::isalnum(ch) || ch == '/' || ch == '.' || ch == '-' || ch == '_' || ch == '~') {
      uri += static_cast<char>(ch);
    } else {
      char buffer[4];
      std::snprintf(buffer, sizeof(buffer), "%%%02X", ch);
      uri += buffer;
    }
  }
  return uri + "?" + query;
}

// Wraps failures of the first reads (corrupt page 1, not a database) with "cannot open".
schema::FileState inspect(Connection& c) {
  try {
    return schema::inspect(c);
  } catch (const DatabaseError& e) {
    const std::string what = e.what();
    if (what.rfind("cannot open", 0) == 0 || what.rfind("database ", 0) == 0) throw;
    throw DatabaseError("cannot open database " + c.path() + ": it cannot be read (" + what + ")");
  }
}

}  // namespace

std::unique_ptr<Connection> writer(const std::string& path, const Database::Options& options,
                                   int* schemaVersion) {
  files::checkBeforeOpen(path, false, options.createIfMissing);
  const int flags = SQLITE_OPEN_READWRITE | (options.createIfMissing ? SQLITE_OPEN_CREATE : 0);
  auto c = std::make_unique<Connection>(path, flags, path);
  if (c->isReadOnly()) {
    throw DatabaseError("cannot open database " + path +
                        " for writing: SQLite opened it read-only (permission denied); open it read-only to read it");
  }
  const schema::FileState state = inspect(*c);
  schema::requireUsable(state, path, false);
  // The page size of a new file can only be chosen before its first table (and before WAL).
  if (state.kind == schema::Kind::kEmpty) c->exec("PRAGMA page_size = " + std::to_string(options.pageSize));
  writerPragmas(*c, options);
  schema::createOrUpgrade(*c, state);
  *schemaVersion = kSchemaVersion;
  return c;
}

std::unique_ptr<Connection> reader(const std::string& path, const Database::Options& options,
                                   bool checkSchema, int* schemaVersion) {
  if (checkSchema) files::checkBeforeOpen(path, true, false);
  auto c = std::make_unique<Connection>(path, SQLITE_OPEN_READONLY, path);
  schema::FileState state;
  try {
    state = inspect(*c);
  } catch (const DatabaseError&) {
    // A WAL database needs its -shm file even to read. In a directory we cannot write, with
    // no WAL left behind (cleanly closed), the file is complete on its own: read it immutable.
    std::error_code ec;
    const std::filesystem::path dir = std::filesystem::absolute(path).parent_path();
    if (!checkSchema || ::access(dir.c_str(), W_OK) == 0 || std::filesystem::exists(path + "-wal", ec)) throw;
    c = std::make_unique<Connection>(fileUri(path, "immutable=1"), SQLITE_OPEN_READONLY, path);
    state = inspect(*c);
  }
  if (checkSchema) {
    schema::requireUsable(state, path, true);
    *schemaVersion = state.version;
  }
  commonPragmas(*c, options);
  return c;
}

}  // namespace rtabmap::db::open

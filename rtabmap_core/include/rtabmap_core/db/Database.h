#pragma once
// The long-term memory (LTM, T-RO 2013 section 3): an SQLite database holding every node that
// left the Working Memory, with its words, links and compressed sensor data, across sessions.
//
// Writing is asynchronous. save*() queue the operation for a background writer thread (the
// paper's "trash" thread: transferring nodes to the LTM must never make the real-time update
// wait on the disk) and return at once with a ticket. The writer groups queued operations
// into transactions; a node, its new words, its links and its sensor data always commit
// together, so the file never holds part of a node. flush() waits until everything queued is
// committed; close() flushes. Commits are acknowledged through WriterStatus (last durable
// node, durable ticket) and the Options::onCommitted callback.
//
// Reading happens on the caller's thread, on a second connection (WAL lets one writer and
// readers work at once). Loads of nodes, links and words see operations still queued, as if
// they had been written; whole-database queries (nodeIds(), loadAllLinks(), summary()...) first
// wait for the queue to drain.
//
// Threads: save*(), loads and queries may be called from any thread; open() and close() must
// not run concurrently with other calls on the same Database.
//
// Errors never crash and never yield a silent empty map: opening a database of a newer schema,
// a corrupt or foreign file, a read-only file or directory or a missing directory throws
// DatabaseError with the reason. A write failure (disk full...) stops the writer: what was
// committed stays, writerStatus() tells the error, and later save*()/flush() throw it until
// the writer tries again, 5 s after the failure, with what is queued (space freed on a full
// disk is used again).
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rtabmap_core/db/Types.h"
#include "rtabmap_core/db/Version.h"
#include "rtabmap_core/memory/Link.h"
#include "rtabmap_core/memory/Signature.h"

namespace rtabmap::db {

// How to open the long-term memory (Database::Options).
struct DatabaseOptions {
  // PRAGMA journal_mode (DbSqlite3/JournalMode: the original's numbering, WAL added as 5).
  enum class JournalMode { kDelete = 0, kTruncate = 1, kPersist = 2, kMemory = 3, kOff = 4, kWal = 5 };
  // PRAGMA synchronous (DbSqlite3/Synchronous).
  enum class Synchronous { kOff = 0, kNormal = 1, kFull = 2 };

  // Opens the file read-only: no session, no writer thread; save*() throw.
  bool readOnly = false;
  // Creates the file if it does not exist (for writing only).
  bool createIfMissing = true;

  // WAL is what lets loads run while the writer writes, and keeps the file intact if the
  // process dies mid-transaction. Other modes serialise readers and the writer (readers
  // wait on busyTimeoutMs); MEMORY and OFF can corrupt the file on a crash.
  JournalMode journalMode = JournalMode::kWal;
  // With WAL: NORMAL syncs only at checkpoints; a committed transaction survives a crash of
  // the process (it is in the OS page cache) but the last ones may be lost on power loss,
  // never corrupting the file. FULL syncs the WAL at every commit, so every acknowledged
  // node also survives power loss, at the price of one fsync per transaction (the writer
  // pays it, not the caller). OFF never syncs: a power loss may corrupt the file.
  Synchronous synchronous = Synchronous::kNormal;
  // Page cache of each connection, in pages (DbSqlite3/CacheSize, same default: 16 MB).
  int cacheSize = 1000;
  // Where temporary tables and indices live (DbSqlite3/TempStore): 0 default, 1 file, 2 memory.
  int tempStore = 2;
  // Page size of a new database, in bytes (a power of two, 512..65536; an existing file keeps
  // its own). See Schema.cpp for the measurement behind the default.
  int pageSize = 16384;
  // How long a connection waits for a lock held by another process before failing.
  int busyTimeoutMs = 5000;
  // Limit on the file size in pages (0: none). Reaching it fails writes with SQLITE_FULL,
  // exactly like a full disk, which is how tests exercise that path.
  int64_t maxPageCount = 0;

  // Nodes per transaction: larger batches amortise the commit when the writer lags behind.
  int maxBatchNodes = 32;
  // Back-pressure: save() blocks while this many nodes wait for the writer (0: no limit).
  // Keeps memory bounded if the disk cannot keep up with the robot.
  int maxPendingNodes = 1000;
  // Codec for images given raw only (compressed by the writer thread).
  std::string imageFormat = ".jpg";

  // Parameters of the new session (the params area's serialised ParametersMap).
  std::string sessionParameters;
  // Called on the writer thread after each commit: the acknowledgement of what is now durable
  // (node ids in save order, ticket, write time). It runs before flush() waiters covering
  // that commit are released, so when flush() returns every covered node was acknowledged.
  // Keep it short; it must not call save*() or flush().
  std::function<void(const CommitInfo& commit)> onCommitted;

  // Ceres-style validation: false and the reason in *why when a field is out of range.
  bool IsValid(std::string* why) const;
  // The DbSqlite3/* parameters (defaults for absent keys). Throws ParameterError on an
  // invalid value, and for DbSqlite3/InMemory = true, which this long-term memory does not
  // offer (it would lose the session on a crash, against what the writer guarantees).
  static DatabaseOptions fromParameters(const std::map<std::string, std::string>& parameters);
};

class Database {
 public:
  using Options = DatabaseOptions;

  Database();
  // Opens (see open()).
  explicit Database(const std::string& path, const Options& options = Options());
  // Closes; errors are logged (call close() to get them).
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  // Opens or creates the database, upgrading an older schema when opened for writing. For
  // writing, starts a new session (new map id) and the writer thread. Throws DatabaseError
  // (newer version, corrupt or foreign file, permissions, missing directory) or
  // std::invalid_argument (invalid options).
  void open(const std::string& path, const Options& options = Options());
  // Waits for the writer, ends the session, closes. Throws DatabaseError if queued operations
  // could not be written (the file is closed all the same).
  void close();
  bool isOpen() const;
  const std::string& path() const;
  bool isReadOnly() const;
  int schemaVersion() const;
  // The session opened for writing and its map id (-1 when read-only).
  int sessionId() const;
  int sessionMapId() const;

  // ---------------------------------------------------------------------- writing (async)
  // Each returns a ticket (increasing); WriterStatus::durableTicket says when it committed.
  // Throws DatabaseError if read-only or if the writer has failed.

  // Saves a node: its row, links (from it; temporary links are skipped), words (features)
  // and sensor data, with the visual words it introduced into the dictionary, in one
  // transaction. Saving a node already saved replaces it; then an empty word list or empty
  // sensor data keep what is stored (a node reloaded without its data can be saved again).
  uint64_t saveNode(Signature node, std::vector<StoredWord> newWords = {});
  uint64_t saveWords(std::vector<StoredWord> words);
  // Adds or replaces a link (type and endpoints identify it), in both directions.
  uint64_t saveLink(const Link& link);
  // Removes the links between two nodes of this type (kUndef: all), in both directions.
  uint64_t removeLink(int from, int to, Link::Type type = Link::kUndef);
  uint64_t updateNode(const NodeUpdate& update);
  uint64_t saveStatistics(const StoredStatistics& statistics);
  uint64_t setSessionParameters(const std::string& parameters);

  // Blocks until every operation queued so far is committed. Throws DatabaseError if the
  // writer failed.
  void flush();
  WriterStatus writerStatus() const;
  int lastDurableNodeId() const;

  // ------------------------------------------------------------------- per-node reads
  // These see queued operations. A node loaded before its write may still carry raw sensor
  // data instead of (or beside) the compressed form.

  std::optional<Signature> loadNode(int id, const LoadOptions& options = LoadOptions()) const;
  // Nodes in the order of `ids`; ids not found are skipped.
  std::vector<Signature> loadNodes(const std::vector<int>& ids,
                                   const LoadOptions& options = LoadOptions()) const;
  // Links from the node, keyed by the other node's id.
  std::multimap<int, Link> loadLinks(int id) const;
  // Nodes reachable from `id` through links within maxDepth hops (id itself at depth 0),
  // as id -> depth. Landmark and self links are not followed. maxDepth 0: just `id`.
  std::map<int, int> neighborIds(int id, int maxDepth) const;
  std::vector<Signature> loadNeighbors(int id, int maxDepth,
                                       const LoadOptions& options = LoadOptions()) const;
  // Words found, in the order of `ids`.
  std::vector<StoredWord> loadWords(const std::vector<int>& ids) const;
  std::optional<StoredStatistics> loadStatistics(int nodeId) const;
  // Largest ids saved or queued (0 if none): new sessions continue after them.
  int lastNodeId() const;
  int lastWordId() const;
  // Largest map id of any node or session (-1 if none).
  int lastMapId() const;

  // ---------------------------------------------------------- whole-database reads
  // These wait until queued operations are written (not if the writer failed).

  std::vector<int> nodeIds() const;
  // Ids of the intermediate nodes (weight -1, Rtabmap/CreateIntermediateNodes), ascending.
  std::vector<int> intermediateNodeIds() const;
  // Every node without links, words or sensor data (pose graph, labels, weights).
  std::map<int, Signature> loadAllNodeHeaders() const;
  // Every link, keyed by from id. Each constraint appears once (bothDirections = false) or
  // as stored, once from each end.
  std::multimap<int, Link> loadAllLinks(bool bothDirections = false) const;
  std::map<int, std::string> labels() const;
  std::vector<SessionInfo> sessions() const;
  // Parameters of the most recent session ("" if none).
  std::string lastSessionParameters() const;
  DatabaseSummary summary() const;
  // Cross-table checks (cheap); full = true adds word references and PRAGMA quick_check
  // (reads the whole file).
  ConsistencyReport checkConsistency(bool full = false) const;
  // Bytes on disk: the database file and its WAL.
  int64_t sizeOnDisk() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rtabmap::db

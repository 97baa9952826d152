#include "Schema.h"

#include <algorithm>
#include <ctime>
#include <regex>
#include <set>
#include <vector>

#include "Sqlite.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/db/Version.h"

namespace rtabmap::db::schema {

namespace {

// Schema steps: step i turns a version i-1 database into version i. A new database runs them
// all from 0, an older one the missing ones, so creation and upgrade share one path. Later
// issues append steps (global descriptors, landmarks...) and raise kSchemaVersion.
//
// Layout decisions (measured with 500 features of 32-byte descriptors per node, 20,000 nodes,
// WAL + synchronous NORMAL, one node per transaction, warm cache):
//
//  * Node-word features are packed, one Feature row per node holding four arrays (word id
//    per keypoint, keypoints, 3D points, descriptors), rather than one row per feature with
//    an index on node id as the original's Map_Node_Word:
//                         save/node   load/node   bytes/node
//        row per feature    0.80 ms     0.20 ms     65,400
//        packed per node    0.05 ms     0.015 ms    38,400
//    Rows cost one B-tree insert (plus one index insert) per feature and 26 bytes of row and
//    index overhead each; the packed row is one insert and one lookup. What rows would allow,
//    "which nodes have word w" in SQL, is the vocabulary's in-memory inverted index's job.
//
//  * Features, sensor data and the node row are three tables keyed by node id, not one: the
//    pose graph (all Node rows) is read at start-up and by tools; kept apart from the ~40 kB
//    of features and the images of each node, it stays a few MB for 100,000 nodes. The
//    feature count is duplicated in Node.word_count for the same reason (summary counts
//    without touching Feature pages).
//
//  * Within Data, columns go from small to large (calibration ... image): SQLite walks a
//    row's overflow chain up to the last column read, so a scan or grid load that skips the
//    images never reads their pages.
//
//  * Links are stored once from each end (as the original), in a WITHOUT ROWID table keyed
//    (from_id, to_id, type): the links of a node are one contiguous key range, read with one
//    seek. Information matrices take 6 doubles when diagonal (48 bytes instead of 288).
//
//  * Pages of 16 KiB (Options::pageSize) instead of SQLite's 4 KiB: a node's ~40 kB feature
//    row then spans 3 pages instead of 10, each page being one read() when it is not in
//    SQLite's cache. Measured with bench-db_bench, 20,000 nodes of 500 words (warm OS cache):
//        page     writer/node   load at 1,000 -> 20,000 nodes   bytes/node
//        4 KiB     0.29 ms      0.121 -> 0.208 ms (x1.72)        52,300
//        8 KiB     0.20 ms      0.114 -> 0.125 ms (x1.10)        55,000
//        16 KiB    0.16 ms      0.107 -> 0.115 ms (x1.07)        56,400
//        32 KiB    0.13 ms      0.110 -> 0.126 ms (x1.14)        56,400
//        64 KiB    0.18 ms      0.121 -> 0.123 ms (x1.02)        80,500
//    With 4 KiB pages the load time grows once the file outgrows SQLite's page cache; from
//    16 KiB on it stays flat, for 8% more bytes (the partly filled last page of each row).
//
//  * Poses are 12 doubles (exact round trip; 96 bytes are noise next to the features).
//
//  * No foreign keys: the writer keeps tables consistent within its transactions, and
//    checkConsistency() verifies it; enforcing them would cost an index probe per insert.
const std::vector<const char*> kSteps = {
    // ---------------------------------------------------------------- version 1
    R"SQL(
CREATE TABLE Admin (
  id INTEGER PRIMARY KEY CHECK (id = 1),
  schema_version INTEGER NOT NULL,
  created_by TEXT NOT NULL,      -- rtabmap_ros version that created the file
  written_by TEXT NOT NULL,      -- rtabmap_ros version that last opened it for writing
  created_time REAL NOT NULL     -- unix time
);
CREATE TABLE Session (
  id INTEGER PRIMARY KEY,        -- 1, 2, ... one per open for writing
  map_id INTEGER NOT NULL,       -- first map id of the session
  start_time REAL NOT NULL,
  end_time REAL,                 -- NULL: still open, or the process died
  rtabmap_ros_version TEXT NOT NULL,
  parameters TEXT NOT NULL DEFAULT ''
);
CREATE TABLE Node (
  id INTEGER PRIMARY KEY,
  map_id INTEGER NOT NULL,
  weight INTEGER NOT NULL,
  stamp REAL NOT NULL,
  label TEXT,                    -- NULL: no label
  pose BLOB,                     -- 12 doubles; NULL: null transform
  ground_truth_pose BLOB,
  velocity BLOB,                 -- 6 floats or NULL
  word_count INTEGER NOT NULL,   -- features in the Feature row
  time_enter REAL NOT NULL       -- unix time of the last write
);
CREATE INDEX Node_label ON Node(label) WHERE label IS NOT NULL;
CREATE TABLE Data (
  id INTEGER PRIMARY KEY,        -- node id
  calibration BLOB,              -- camera models (CameraModel/StereoCameraModel::serialize)
  scan_info BLOB,
  cell_size REAL,
  view_point BLOB,
  imu BLOB,
  gps BLOB,
  scan BLOB,                     -- codec::compressData of the scan points
  user_data BLOB,
  ground_cells BLOB,             -- codec::compressData of the local grid
  obstacle_cells BLOB,
  empty_cells BLOB,
  depth BLOB,                    -- compressed depth, or right image of a stereo pair
  image BLOB                     -- compressed RGB or left image
);
CREATE TABLE Feature (
  node_id INTEGER PRIMARY KEY,
  word_ids BLOB,                 -- int32 per keypoint
  keypoints BLOB,                -- 28 bytes per keypoint
  points BLOB,                   -- 3 floats per keypoint, or NULL
  descriptors BLOB               -- type, rows, cols + rows
);
CREATE TABLE Word (
  id INTEGER PRIMARY KEY,
  descriptor BLOB NOT NULL       -- type, rows (1), cols + data
);
CREATE TABLE Link (
  from_id INTEGER NOT NULL,
  to_id INTEGER NOT NULL,
  type INTEGER NOT NULL,
  transform BLOB NOT NULL,
  information BLOB NOT NULL,
  user_data BLOB,
  PRIMARY KEY (from_id, to_id, type)
) WITHOUT ROWID;
CREATE TABLE Statistics (
  node_id INTEGER PRIMARY KEY,
  stamp REAL NOT NULL,
  data BLOB,                     -- zlib of "key value" lines
  wm_state BLOB                  -- zlib of int32 ids
);
)SQL",
};

std::string tableList(Connection& connection) {
  std::string names;
  int count = 0;
  Query q = connection.query(
      "SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY name LIMIT 6");
  while (q->step()) {
    if (++count > 5) {
      names += ", ...";
      break;
    }
    if (!names.empty()) names += ", ";
    names += q->columnText(0);
  }
  return names;
}

// The tables a file of schema `version` has: those its steps create, less those they drop.
std::vector<std::string> tablesOfVersion(int version) {
  static const std::regex statement(R"((CREATE|DROP) TABLE (?:IF (?:NOT )?EXISTS )?(\w+))");
  std::vector<std::string> tables;
  for (int v = 1; v <= version && v <= static_cast<int>(kSteps.size()); ++v) {
    const std::string step = kSteps[v - 1];
    for (std::sregex_iterator it(step.begin(), step.end(), statement), end; it != end; ++it) {
      const std::string name = (*it)[2];
      tables.erase(std::remove(tables.begin(), tables.end(), name), tables.end());
      if ((*it)[1] == "CREATE") tables.push_back(name);
    }
  }
  return tables;
}

// A table dropped by hand or lost with a damaged page would otherwise surface in the middle
// of a load or in the writer thread, after the file was already written to (a new session).
std::string missingTables(Connection& connection, int version) {
  std::set<std::string> present;
  Query q = connection.query("SELECT name FROM sqlite_master WHERE type = 'table'");
  while (q->step()) present.insert(q->columnText(0));
  std::string missing;
  for (const std::string& table : tablesOfVersion(version)) {
    if (!present.count(table)) missing += (missing.empty() ? "" : ", ") + table;
  }
  return missing;
}

}  // namespace

FileState inspect(Connection& connection) {
  FileState state;
  // The first read of the file: a corrupt header or a non-database fails here.
  const int64_t tables = connection.scalar("SELECT count(*) FROM sqlite_master WHERE type = 'table'");
  const int64_t applicationId = connection.scalar("PRAGMA application_id");
  if (applicationId == kApplicationId) {
    state.kind = Kind::kOurs;
    state.version = static_cast<int>(connection.scalar("PRAGMA user_version"));
    const bool hasAdmin =
        connection.scalar("SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = 'Admin'") > 0;
    if (hasAdmin) {
      try {
        // Every schema version must keep these two columns: they name the writer in the
        // "newer version" message.
        Query q = connection.query("SELECT created_by, written_by FROM Admin WHERE id = 1");
        if (q->step()) {
          state.createdBy = q->columnText(0);
          state.lastWrittenBy = q->columnText(1);
        }
      } catch (const DatabaseError&) {
        if (state.version <= kSchemaVersion) throw;
        state.createdBy = state.lastWrittenBy = "an unknown version";
      }
    }
    if (state.createdBy.empty()) {
      throw DatabaseError("database " + connection.path() +
                          " is damaged: its Admin table (schema version and writer) is missing");
    }
    if (state.version <= kSchemaVersion) state.missingTables = missingTables(connection, state.version);
  } else if (tables == 0) {
    state.kind = Kind::kEmpty;
  } else {
    state.kind = Kind::kForeign;
    state.foreignTables = tableList(connection);
  }
  return state;
}

void requireUsable(const FileState& state, const std::string& path, bool readOnly) {
  if (state.kind == Kind::kForeign) {
    throw DatabaseError("database " + path +
                        " is an SQLite database but not an rtabmap_ros long-term memory "
                        "(tables: " + state.foreignTables + ")");
  }
  if (state.kind == Kind::kEmpty && readOnly) {
    throw DatabaseError("database " + path + " is empty (no rtabmap_ros table)");
  }
  if (state.kind != Kind::kOurs) return;
  if (state.version > kSchemaVersion) {
    throw DatabaseError("database " + path + ": database version " + std::to_string(state.version) +
                        " was written by a newer rtabmap_ros (" + state.lastWrittenBy +
                        "); this build reads up to " + std::to_string(kSchemaVersion));
  }
  if (state.version < 1) {
    throw DatabaseError("database " + path + " is damaged: its schema version is " +
                        std::to_string(state.version));
  }
  if (!state.missingTables.empty()) {
    throw DatabaseError("database " + path + " is damaged: table(s) " + state.missingTables +
                        " of schema version " + std::to_string(state.version) + " missing");
  }
  if (state.version < kSchemaVersion && readOnly) {
    throw DatabaseError("database " + path + ": database version " + std::to_string(state.version) +
                        " is older than this build's (" + std::to_string(kSchemaVersion) +
                        "); open it once for writing to upgrade it");
  }
}

void createOrUpgrade(Connection& connection, const FileState& state) {
  Transaction transaction(connection);
  const int from = state.kind == Kind::kOurs ? state.version : 0;
  for (int version = from + 1; version <= kSchemaVersion; ++version) {
    connection.exec(kSteps.at(version - 1));
  }
  if (from == 0) {
    connection.exec("PRAGMA application_id = " + std::to_string(kApplicationId));
    Query q = connection.query(
        "INSERT INTO Admin (id, schema_version, created_by, written_by, created_time) "
        "VALUES (1, ?, ?, ?, ?)");
    q->bind(1, kSchemaVersion).bind(2, std::string(kRtabmapRosVersion))
        .bind(3, std::string(kRtabmapRosVersion)).bind(4, static_cast<double>(std::time(nullptr)));
    q->run();
  } else {
    Query q = connection.query("UPDATE Admin SET schema_version = ?, written_by = ? WHERE id = 1");
    q->bind(1, kSchemaVersion).bind(2, std::string(kRtabmapRosVersion));
    q->run();
  }
  // PRAGMA takes no bound parameter; the value is our own integer constant.
  connection.exec("PRAGMA user_version = " + std::to_string(kSchemaVersion));
  transaction.commit();
}

}  // namespace rtabmap::db::schema

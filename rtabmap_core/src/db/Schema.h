#pragma once
// The versioned schema of the long-term memory: creation, identification of our files and
// step-by-step upgrades.
#include <string>

namespace rtabmap::db {

class Connection;

namespace schema {

// What an opened SQLite file is.
enum class Kind {
  kEmpty,    // no table at all: a new database
  kOurs,     // application_id is ours
  kForeign,  // some other SQLite database
};

struct FileState {
  Kind kind = Kind::kEmpty;
  int version = 0;             // PRAGMA user_version (ours only)
  std::string createdBy;       // Admin.created_by
  std::string lastWrittenBy;   // Admin.written_by
  std::string foreignTables;   // a few table names of a foreign file, for the message
  std::string missingTables;   // ours: tables its schema version has that the file lacks
};

// Reads the identity of the file. Throws DatabaseError if SQLite cannot read it (corrupt,
// not a database).
FileState inspect(Connection& connection);

// Throws DatabaseError with a message for the user if this build cannot use the file:
// foreign file, newer version (always), older version opened read-only (cannot upgrade),
// a table of its version missing (damaged: refused before anything is written to it).
void requireUsable(const FileState& state, const std::string& path, bool readOnly);

// Creates every table (empty file) or applies the missing steps (older version), in one
// transaction, and records this build in Admin.written_by.
void createOrUpgrade(Connection& connection, const FileState& state);

}  // namespace schema
}  // namespace rtabmap::db

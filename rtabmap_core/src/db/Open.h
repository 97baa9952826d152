#pragma once
// Opening the two connections of a database: the writer's (read-write, owns the schema and the
// session) and the reader's (read-only), with their pragmas.
#include <memory>
#include <string>

#include "rtabmap_core/db/Database.h"
#include "Schema.h"

namespace rtabmap::db {

class Connection;

namespace open {

// Read-write connection on an existing or new file, schema created or upgraded, pragmas set.
// Throws DatabaseError with the reason.
std::unique_ptr<Connection> writer(const std::string& path, const Database::Options& options,
                                   int* schemaVersion);
// Read-only connection. `checkSchema`: inspect the file and refuse it if unusable (when there
// is no writer connection that already did). Falls back to SQLite's immutable mode when a WAL
// database sits in a directory where its -shm cannot be created.
std::unique_ptr<Connection> reader(const std::string& path, const Database::Options& options,
                                   bool checkSchema, int* schemaVersion);

}  // namespace open
}  // namespace rtabmap::db

#pragma once
// Checks of the database path made before SQLite touches it, so that the usual mistakes get a
// message naming the path and the cause rather than SQLite's "unable to open database file".
#include <string>

namespace rtabmap::db::files {

// Throws DatabaseError if the file cannot be opened in this mode: missing directory, path is
// a directory, file missing (read-only or createIfMissing = false), file or directory not
// writable (for writing), or a file that is not a complete SQLite database (wrong header,
// truncated). Returns whether the file exists.
bool checkBeforeOpen(const std::string& path, bool readOnly, bool createIfMissing);

// Bytes of the file and of its -wal beside it (0 for missing files).
long long sizeOnDisk(const std::string& path);

}  // namespace rtabmap::db::files

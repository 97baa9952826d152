#include "FileChecks.h"

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "rtabmap_core/common/Error.h"

namespace fs = std::filesystem;

namespace rtabmap::db::files {

namespace {

constexpr char kSqliteMagic[16] = "SQLite format 3";  // + the terminating NUL: 16 bytes

uint32_t bigEndian32(const unsigned char* p) {
  return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | uint32_t(p[3]);
}

[[noreturn]] void fail(const std::string& path, const std::string& why) {
  throw DatabaseError("cannot open database " + path + ": " + why);
}

// The 100-byte SQLite header (https://www.sqlite.org/fileformat.html): magic string, page
// size at 16, change counter at 24, database size in pages at 28, "version-valid-for" at 92.
// The in-header size is trusted when version-valid-for equals the change counter. A file
// shorter than that size was cut (an interrupted copy, a full disk while copying): SQLite
// itself would only notice when it reaches a missing page, deep inside some later query.
void checkHeader(const std::string& path, uintmax_t fileSize) {
  if (fileSize == 0) return;  // an empty file is an empty database
  unsigned char header[100];
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "the file cannot be read (" + std::string(std::strerror(errno)) + ")");
  in.read(reinterpret_cast<char*>(header), sizeof(header));
  const std::streamsize got = in.gcount();
  if (got < 16 || std::memcmp(header, kSqliteMagic, 16) != 0) {
    fail(path, "the file is not an SQLite database (corrupt, or another kind of file)");
  }
  if (got < static_cast<std::streamsize>(sizeof(header))) {
    fail(path, "the file is truncated (" + std::to_string(fileSize) + " bytes, shorter than the SQLite header)");
  }
  uint32_t pageSize = (uint32_t(header[16]) << 8) | header[17];
  if (pageSize == 1) pageSize = 65536;
  if (pageSize < 512 || (pageSize & (pageSize - 1)) != 0) {
    fail(path, "the file is corrupt (invalid page size " + std::to_string(pageSize) + " in its header)");
  }
  const uint32_t changeCounter = bigEndian32(header + 24);
  const uint32_t pages = bigEndian32(header + 28);
  const uint32_t validFor = bigEndian32(header + 92);
  // A WAL beside the file may legitimately hold pages a checkpoint had not finished moving.
  std::error_code ec;
  const bool walPresent = fs::exists(path + "-wal", ec) && fs::file_size(path + "-wal", ec) > 0;
  if (pages > 0 && validFor == changeCounter && !walPresent) {
    const uintmax_t expected = uintmax_t(pages) * pageSize;
    if (fileSize < expected) {
      fail(path, "the file is truncated: its header announces " + std::to_string(pages) +
                     " pages (" + std::to_string(expected) + " bytes) but it has " +
                     std::to_string(fileSize) + " bytes");
    }
  }
}

}  // namespace

bool checkBeforeOpen(const std::string& path, bool readOnly, bool createIfMissing) {
  if (path.empty()) throw DatabaseError("cannot open database: no path given");
  std::error_code ec;
  const fs::path file(path);
  fs::path dir = file.parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::exists(dir, ec)) fail(path, "directory " + dir.string() + " does not exist");
  if (!fs::is_directory(dir, ec)) fail(path, dir.string() + " is not a directory");

  const bool exists = fs::exists(file, ec);
  if (exists) {
    if (fs::is_directory(file, ec)) fail(path, "it is a directory");
    if (::access(path.c_str(), R_OK) != 0) fail(path, "the file is not readable (permission denied)");
    checkHeader(path, fs::file_size(file, ec));
  } else if (readOnly || !createIfMissing) {
    fail(path, "the file does not exist");
  }
  if (readOnly) return exists;

  if (exists && ::access(path.c_str(), W_OK) != 0) {
    fail(path, "the file is read-only (permission denied); open it read-only to read it");
  }
  // The journal (-wal, -shm) is created beside the database, and so is a new file.
  if (::access(dir.c_str(), W_OK) != 0) {
    fail(path, "directory " + dir.string() +
                   " is not writable (permission denied); the database and its journal files "
                   "(-wal, -shm) are written there. Open it read-only to read it");
  }
  return exists;
}

long long sizeOnDisk(const std::string& path) {
  std::error_code ec;
  long long total = 0;
  for (const std::string& p : {path, path + "-wal"}) {
    const uintmax_t size = fs::file_size(p, ec);
    if (!ec) total += static_cast<long long>(size);
  }
  return total;
}

}  // namespace rtabmap::db::files

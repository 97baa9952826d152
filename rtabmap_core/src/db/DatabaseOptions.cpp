#include <sstream>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/db/Version.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap::db {

bool DatabaseOptions::IsValid(std::string* why) const {
  std::ostringstream reason;
  const int journal = static_cast<int>(journalMode);
  const int sync = static_cast<int>(synchronous);
  if (journal < 0 || journal > 5) {
    reason << "journalMode must be 0..5 (DELETE, TRUNCATE, PERSIST, MEMORY, OFF, WAL), got " << journal;
  } else if (sync < 0 || sync > 2) {
    reason << "synchronous must be 0..2 (OFF, NORMAL, FULL), got " << sync;
  } else if (cacheSize < 0) {
    reason << "cacheSize must be >= 0 pages, got " << cacheSize;
  } else if (tempStore < 0 || tempStore > 2) {
    reason << "tempStore must be 0..2 (DEFAULT, FILE, MEMORY), got " << tempStore;
  } else if (pageSize < 512 || pageSize > 65536 || (pageSize & (pageSize - 1)) != 0) {
    reason << "pageSize must be a power of two from 512 to 65536, got " << pageSize;
  } else if (busyTimeoutMs < 0) {
    reason << "busyTimeoutMs must be >= 0, got " << busyTimeoutMs;
  } else if (maxPageCount < 0) {
    reason << "maxPageCount must be >= 0 (0: no limit), got " << maxPageCount;
  } else if (maxBatchNodes < 1) {
    reason << "maxBatchNodes must be >= 1, got " << maxBatchNodes;
  } else if (maxPendingNodes < 0) {
    reason << "maxPendingNodes must be >= 0 (0: no limit), got " << maxPendingNodes;
  } else if (imageFormat.size() < 2 || imageFormat[0] != '.') {
    reason << "imageFormat must be a codec extension such as \".jpg\" or \".png\", got \"" << imageFormat << "\"";
  }
  const std::string text = reason.str();
  if (why) *why = text;
  return text.empty();
}

DatabaseOptions DatabaseOptions::fromParameters(const std::map<std::string, std::string>& parameters) {
  if (Parameters::getBool(parameters, Parameters::kDbSqlite3InMemory())) {
    throw ParameterError(Parameters::kDbSqlite3InMemory() +
                         " = true is not supported: the long-term memory is written as it goes "
                         "so that a crash keeps the session; use false");
  }
  const std::string target = Parameters::getString(parameters, Parameters::kDbTargetVersion());
  if (!target.empty()) {
    // The original's launch files set it to write an older schema; there is only one here.
    RTABMAP_WARN(Parameters::kDbTargetVersion() << " \"" << target << "\" is ignored: databases are written in schema "
                                                << kSchemaVersion << ", the only one this implementation has");
  }
  DatabaseOptions options;
  options.cacheSize = Parameters::getInt(parameters, Parameters::kDbSqlite3CacheSize());
  options.journalMode = static_cast<JournalMode>(Parameters::getInt(parameters, Parameters::kDbSqlite3JournalMode()));
  options.synchronous = static_cast<Synchronous>(Parameters::getInt(parameters, Parameters::kDbSqlite3Synchronous()));
  options.tempStore = Parameters::getInt(parameters, Parameters::kDbSqlite3TempStore());
  return options;
}

}  // namespace rtabmap::db

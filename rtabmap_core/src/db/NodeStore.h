#pragma once
// The SQL that writes operations to the database (called on the writer thread, inside the
// writer's transaction).
#include <string>

#include "Operations.h"

namespace rtabmap::db {

class Connection;

namespace store {

// Writes one operation. `imageFormat` is the codec for images given raw only.
void apply(Connection& connection, const Operation& operation, const std::string& imageFormat);

// New session row; returns its id. `mapId` is the session's first map id.
int insertSession(Connection& connection, int mapId, const std::string& parameters);

}  // namespace store
}  // namespace rtabmap::db

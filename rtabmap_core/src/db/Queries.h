#pragma once
// Whole-database queries (reader connection): listings, counts, consistency checks.
#include <map>
#include <string>
#include <vector>

#include "rtabmap_core/db/Types.h"
#include "rtabmap_core/memory/Link.h"
#include "rtabmap_core/memory/Signature.h"

namespace rtabmap::db {

class Connection;

namespace queries {

std::vector<int> nodeIds(Connection& c);
std::vector<int> intermediateNodeIds(Connection& c);
std::map<int, Signature> nodeHeaders(Connection& c);
std::multimap<int, Link> allLinks(Connection& c, bool bothDirections);
std::map<int, std::string> labels(Connection& c);
std::vector<SessionInfo> sessions(Connection& c);
int maxNodeId(Connection& c);
int maxWordId(Connection& c);
int maxMapId(Connection& c);
DatabaseSummary summary(Connection& c);
ConsistencyReport consistency(Connection& c, bool full);

}  // namespace queries
}  // namespace rtabmap::db

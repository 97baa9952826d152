#pragma once
// The SQL that reads nodes, links, words and statistics (caller thread, reader connection).
#include <map>
#include <optional>

#include "rtabmap_core/db/Types.h"
#include "rtabmap_core/memory/Link.h"
#include "rtabmap_core/memory/Signature.h"

namespace rtabmap::db {

class Connection;
class Statement;

namespace load {

// The node with the parts asked for; flags say saved and unmodified. nullopt if absent.
std::optional<Signature> node(Connection& connection, int id, const LoadOptions& options);
// Links stored from the node, keyed by the other end.
std::multimap<int, Link> links(Connection& connection, int id);
std::optional<StoredWord> word(Connection& connection, int id);
std::optional<StoredStatistics> statistics(Connection& connection, int nodeId);

// The columns of a node row, in the order headerFromRow() reads them.
extern const char* const kNodeColumns;
// A Signature from a row of kNodeColumns (no links, words or sensor data).
Signature headerFromRow(const Statement& row);

}  // namespace load
}  // namespace rtabmap::db

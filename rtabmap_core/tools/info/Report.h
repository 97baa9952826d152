#pragma once
// What rtabmap-info prints about a database: the summary as JSON (the --json line) and as
// text for people.
#include <nlohmann/json.hpp>

#include <optional>
#include <ostream>
#include <string>

#include "rtabmap_core/db/Types.h"

namespace rtabmap::tools::info {

// The summary as one JSON object: version, rtabmap_ros_version, created_by, sessions (array
// with map ids and node counts), session_count, nodes, nodes_per_map, links (type name ->
// count), links_total, words, features, statistics, last_node_id, last_word_id, size_bytes,
// page_size; plus consistency and parameters when given.
nlohmann::json toJson(const db::DatabaseSummary& summary,
                      const std::optional<db::ConsistencyReport>& consistency,
                      const std::optional<std::string>& parameters);

void printText(std::ostream& out, const db::DatabaseSummary& summary,
               const std::optional<db::ConsistencyReport>& consistency,
               const std::optional<std::string>& parameters);

}  // namespace rtabmap::tools::info

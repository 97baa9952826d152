#include "info/Report.h"

#include <ctime>
#include <iomanip>
#include <sstream>

#include "rtabmap_core/memory/Link.h"

namespace rtabmap::tools::info {

namespace {

// "2024-05-01 14:03:12" (local time), or "-" for 0 (a session that did not close cleanly).
std::string formatTime(double unixTime) {
  if (unixTime <= 0.0) return "-";
  const std::time_t t = static_cast<std::time_t>(unixTime);
  std::tm local{};
  localtime_r(&t, &local);
  std::ostringstream out;
  out << std::put_time(&local, "%Y-%m-%d %H:%M:%S");
  return out.str();
}

std::string formatBytes(int64_t bytes) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(1);
  if (bytes >= (int64_t(1) << 30)) out << bytes / double(int64_t(1) << 30) << " GiB";
  else if (bytes >= (int64_t(1) << 20)) out << bytes / double(int64_t(1) << 20) << " MiB";
  else if (bytes >= 1024) out << bytes / 1024.0 << " KiB";
  else out << std::setprecision(0) << bytes << " bytes";
  return out.str();
}

// Parameters are stored "Key=value;Key=value" (params serialisation); one per line reads better.
void printParameters(std::ostream& out, const std::string& parameters) {
  if (parameters.empty()) {
    out << "Parameters of the last session: none stored\n";
    return;
  }
  out << "Parameters of the last session:\n";
  std::istringstream entries(parameters);
  std::string entry;
  while (std::getline(entries, entry, ';')) {
    if (!entry.empty()) out << "  " << entry << "\n";
  }
}

}  // namespace

nlohmann::json toJson(const db::DatabaseSummary& s, const std::optional<db::ConsistencyReport>& consistency,
                      const std::optional<std::string>& parameters) {
  nlohmann::json j;
  j["path"] = s.path;
  j["version"] = s.schemaVersion;
  j["rtabmap_ros_version"] = s.lastWrittenBy;
  j["created_by"] = s.createdBy;
  nlohmann::json sessions = nlohmann::json::array();
  for (const db::SessionSummary& session : s.sessions) {
    sessions.push_back({{"id", session.info.id},
                        {"map_id", session.info.mapId},
                        {"nodes", session.nodes},
                        {"start_time", session.info.startTime},
                        {"end_time", session.info.endTime},
                        {"rtabmap_ros_version", session.info.rtabmapRosVersion}});
  }
  j["sessions"] = sessions;
  j["session_count"] = s.sessions.size();
  j["nodes"] = s.nodes;
  j["intermediate_nodes"] = s.intermediateNodes;
  nlohmann::json maps = nlohmann::json::object();
  for (const auto& [mapId, nodes] : s.nodesPerMap) maps[std::to_string(mapId)] = nodes;
  j["nodes_per_map"] = maps;
  nlohmann::json links = nlohmann::json::object();
  for (const auto& [type, count] : s.linksPerType) links[Link::typeName(type)] = count;
  j["links"] = links;
  j["links_total"] = s.links;
  j["words"] = s.words;
  j["features"] = s.features;
  j["statistics"] = s.statistics;
  j["last_node_id"] = s.lastNodeId;
  j["last_word_id"] = s.lastWordId;
  j["size_bytes"] = s.fileBytes;
  j["page_size"] = s.pageSize;
  if (consistency) {
    j["consistency"] = {{"ok", consistency->ok()},
                        {"nodes_without_data", consistency->nodesWithoutData},
                        {"nodes_without_features", consistency->nodesWithoutFeatures},
                        {"data_without_node", consistency->dataWithoutNode},
                        {"features_without_node", consistency->featuresWithoutNode},
                        {"feature_count_mismatch", consistency->featureCountMismatch},
                        {"missing_words", consistency->missingWords},
                        {"integrity", consistency->integrity}};
  }
  if (parameters) j["parameters"] = *parameters;
  return j;
}

void printText(std::ostream& out, const db::DatabaseSummary& s,
               const std::optional<db::ConsistencyReport>& consistency,
               const std::optional<std::string>& parameters) {
  out << "Database:        " << s.path << "\n";
  out << "Size on disk:    " << formatBytes(s.fileBytes) << " (" << s.fileBytes << " bytes)\n";
  out << "Schema version:  " << s.schemaVersion << " (created by rtabmap_ros " << s.createdBy
      << ", last written by " << s.lastWrittenBy << ")\n";
  out << "Sessions:        " << s.sessions.size() << "\n";
  for (const db::SessionSummary& session : s.sessions) {
    out << "  session " << session.info.id << ": map " << session.info.mapId << ", " << session.nodes
        << " nodes, " << formatTime(session.info.startTime) << " -> " << formatTime(session.info.endTime)
        << (session.info.endTime <= 0.0 ? " (not closed cleanly)" : "") << ", rtabmap_ros "
        << session.info.rtabmapRosVersion << "\n";
  }
  out << "Nodes:           " << s.nodes << " (last id " << s.lastNodeId << ")";
  if (s.intermediateNodes > 0) out << ", " << s.intermediateNodes << " of them intermediate";
  out << "\n";
  for (const auto& [mapId, nodes] : s.nodesPerMap) out << "  map " << mapId << ": " << nodes << " nodes\n";
  out << "Links:           " << s.links << "\n";
  for (const auto& [type, count] : s.linksPerType) {
    out << "  " << std::left << std::setw(18) << Link::typeName(type) << std::right << count << "\n";
  }
  out << "Words:           " << s.words << " (last id " << s.lastWordId << ")\n";
  out << "Features:        " << s.features;
  if (s.nodes > 0) out << " (" << s.features / s.nodes << " per node)";
  out << "\n";
  out << "Statistics:      " << s.statistics << " nodes\n";
  if (consistency) {
    out << "Consistency:     " << (consistency->ok() ? "ok" : "PROBLEMS FOUND") << " (" << consistency->toString()
        << ")\n";
  }
  if (parameters) printParameters(out, *parameters);
}

}  // namespace rtabmap::tools::info

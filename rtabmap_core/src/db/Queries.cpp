#include "Queries.h"

#include <algorithm>
#include <limits>
#include <sstream>
#include <unordered_set>

#include "Blobs.h"
#include "FileChecks.h"
#include "NodeLoad.h"
#include "Sqlite.h"
#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap::db {

std::string ConsistencyReport::toString() const {
  std::ostringstream out;
  out << "nodes without data: " << nodesWithoutData << ", nodes without features: " << nodesWithoutFeatures
      << ", data without node: " << dataWithoutNode << ", features without node: " << featuresWithoutNode
      << ", feature count mismatches: " << featureCountMismatch << ", missing words: " << missingWords
      << ", integrity: " << integrity;
  return out.str();
}

namespace queries {

namespace {

// Each constraint once: a link stored from both ends is taken from its smaller id; one stored
// from a single end (landmark, or other end never saved) is taken as it is.
const char* const kUniqueLinks =
    "FROM Link AS l WHERE l.from_id <= l.to_id OR NOT EXISTS (SELECT 1 FROM Link AS r "
    "WHERE r.from_id = l.to_id AND r.to_id = l.from_id AND r.type = l.type)";

Link linkFromRow(const Statement& q) {
  size_t size = 0;
  const unsigned char* transform = q.columnBlob(3, &size);
  const Transform t = blob::decodeTransform(transform, size);
  const unsigned char* information = q.columnBlob(4, &size);
  const Link::InfMatrix info = blob::decodeInformation(information, size);
  const unsigned char* userData = q.columnBlob(5, &size);
  return Link(q.columnInt(0), q.columnInt(1), Link::typeFromInt(q.columnInt(2)), t, info,
              size ? codec::uncompressData(userData, size) : cv::Mat());
}

int64_t count(Connection& c, const std::string& sql) { return c.scalar(sql, 0); }

}  // namespace

std::vector<int> nodeIds(Connection& c) {
  std::vector<int> ids;
  Query q = c.query("SELECT id FROM Node ORDER BY id");
  while (q->step()) ids.push_back(q->columnInt(0));
  return ids;
}

std::vector<int> intermediateNodeIds(Connection& c) {
  std::vector<int> ids;
  Query q = c.query("SELECT id FROM Node WHERE weight = -1 ORDER BY id");
  while (q->step()) ids.push_back(q->columnInt(0));
  return ids;
}

std::map<int, Signature> nodeHeaders(Connection& c) {
  std::map<int, Signature> nodes;
  Query q = c.query(std::string("SELECT ") + load::kNodeColumns + " FROM Node ORDER BY id");
  while (q->step()) {
    Signature node = load::headerFromRow(*q);
    nodes.emplace_hint(nodes.end(), node.id(), std::move(node));
  }
  return nodes;
}

std::multimap<int, Link> allLinks(Connection& c, bool bothDirections) {
  std::multimap<int, Link> links;
  const std::string columns = "SELECT from_id, to_id, type, transform, information, user_data ";
  Query q = c.query(bothDirections ? columns + "FROM Link" : columns + kUniqueLinks);
  try {
    while (q->step()) {
      Link link = linkFromRow(*q);
      links.emplace(link.from(), std::move(link));
    }
  } catch (const FormatError& e) {
    throw DatabaseError(c.path() + ": a link is damaged: " + e.what());
  }
  return links;
}

std::map<int, std::string> labels(Connection& c) {
  std::map<int, std::string> result;
  Query q = c.query("SELECT id, label FROM Node WHERE label IS NOT NULL");
  while (q->step()) result[q->columnInt(0)] = q->columnText(1);
  return result;
}

std::vector<SessionInfo> sessions(Connection& c) {
  std::vector<SessionInfo> result;
  Query q = c.query(
      "SELECT id, map_id, start_time, end_time, rtabmap_ros_version, parameters FROM Session ORDER BY id");
  while (q->step()) {
    SessionInfo s;
    s.id = q->columnInt(0);
    s.mapId = q->columnInt(1);
    s.startTime = q->columnDouble(2);
    s.endTime = q->isNull(3) ? 0.0 : q->columnDouble(3);
    s.rtabmapRosVersion = q->columnText(4);
    s.parameters = q->columnText(5);
    result.push_back(std::move(s));
  }
  return result;
}

int maxNodeId(Connection& c) { return static_cast<int>(c.scalar("SELECT max(id) FROM Node", 0)); }

int maxWordId(Connection& c) { return static_cast<int>(c.scalar("SELECT max(id) FROM Word", 0)); }

int maxMapId(Connection& c) {
  return static_cast<int>(std::max(c.scalar("SELECT max(map_id) FROM Node", -1),
                                   c.scalar("SELECT max(map_id) FROM Session", -1)));
}

DatabaseSummary summary(Connection& c) {
  DatabaseSummary s;
  s.path = c.path();
  s.schemaVersion = static_cast<int>(c.scalar("PRAGMA user_version"));
  {
    Query q = c.query("SELECT created_by, written_by FROM Admin WHERE id = 1");
    if (q->step()) {
      s.createdBy = q->columnText(0);
      s.lastWrittenBy = q->columnText(1);
    }
  }
  {
    Query q = c.query("SELECT map_id, count(*) FROM Node GROUP BY map_id");
    while (q->step()) {
      s.nodesPerMap[q->columnInt(0)] = q->columnInt64(1);
      s.nodes += q->columnInt64(1);
    }
  }
  s.intermediateNodes = c.scalar("SELECT count(*) FROM Node WHERE weight = -1");
  const std::vector<SessionInfo> infos = sessions(c);
  for (size_t i = 0; i < infos.size(); ++i) {
    // A session owns the map ids from its first one up to the next session's first one.
    SessionSummary session{infos[i], 0};
    const int end = i + 1 < infos.size() ? infos[i + 1].mapId : std::numeric_limits<int>::max();
    for (const auto& [mapId, nodes] : s.nodesPerMap) {
      if (mapId >= infos[i].mapId && mapId < end) session.nodes += nodes;
    }
    s.sessions.push_back(std::move(session));
  }
  {
    Query q = c.query(std::string("SELECT type, count(*) ") + kUniqueLinks + " GROUP BY type");
    while (q->step()) {
      s.linksPerType[q->columnInt(0)] = q->columnInt64(1);
      s.links += q->columnInt64(1);
    }
  }
  s.words = count(c, "SELECT count(*) FROM Word");
  s.features = count(c, "SELECT coalesce(sum(word_count), 0) FROM Node");
  s.statistics = count(c, "SELECT count(*) FROM Statistics");
  s.lastNodeId = maxNodeId(c);
  s.lastWordId = maxWordId(c);
  s.pageSize = count(c, "PRAGMA page_size");
  s.pageCount = count(c, "PRAGMA page_count");
  s.fileBytes = files::sizeOnDisk(c.path());
  return s;
}

namespace {

// Word references and descriptor rows of every Feature row (reads every feature).
void checkFeatures(Connection& c, ConsistencyReport& report) {
  std::unordered_set<int> words;
  {
    Query q = c.query("SELECT id FROM Word");
    while (q->step()) words.insert(q->columnInt(0));
  }
  Query q = c.query(
      "SELECT f.word_ids, f.descriptors, n.word_count FROM Feature AS f JOIN Node AS n ON n.id = f.node_id");
  while (q->step()) {
    size_t size = 0;
    const unsigned char* data = q->columnBlob(0, &size);
    const std::vector<int> ids = blob::decodeWordIds(data, size);
    for (int id : ids) report.missingWords += words.count(id) == 0;
    data = q->columnBlob(1, &size);
    if (size && blob::decodeMatrix(data, size).rows != q->columnInt(2)) ++report.featureCountMismatch;
  }
}

}  // namespace

ConsistencyReport consistency(Connection& c, bool full) {
  ConsistencyReport r;
  r.nodesWithoutData = count(c, "SELECT count(*) FROM Node AS n WHERE NOT EXISTS (SELECT 1 FROM Data AS d WHERE d.id = n.id)");
  r.nodesWithoutFeatures = count(c, "SELECT count(*) FROM Node AS n WHERE NOT EXISTS (SELECT 1 FROM Feature AS f WHERE f.node_id = n.id)");
  r.dataWithoutNode = count(c, "SELECT count(*) FROM Data AS d WHERE NOT EXISTS (SELECT 1 FROM Node AS n WHERE n.id = d.id)");
  r.featuresWithoutNode = count(c, "SELECT count(*) FROM Feature AS f WHERE NOT EXISTS (SELECT 1 FROM Node AS n WHERE n.id = f.node_id)");
  // length() of a blob comes from the record header: no blob page is read.
  r.featureCountMismatch = count(c,
      "SELECT count(*) FROM Feature AS f JOIN Node AS n ON n.id = f.node_id WHERE "
      "coalesce(length(f.word_ids), 0) != 4 * n.word_count OR "
      "coalesce(length(f.keypoints), 0) != 28 * n.word_count OR "
      "(f.points IS NOT NULL AND length(f.points) != 12 * n.word_count)");
  if (full) {
    try {
      checkFeatures(c, r);
    } catch (const FormatError& e) {
      r.integrity = std::string("damaged feature row: ") + e.what();
    }
    Query q = c.query("PRAGMA quick_check");
    std::string result;
    while (q->step()) result += (result.empty() ? "" : "; ") + q->columnText(0);
    if (r.integrity == "ok") r.integrity = result;
  }
  return r;
}

}  // namespace queries
}  // namespace rtabmap::db

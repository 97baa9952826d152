#include "NodeLoad.h"

#include <string>
#include <vector>

#include "Blobs.h"
#include "Sqlite.h"
#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap::db::load {

const char* const kNodeColumns =
    "id, map_id, weight, stamp, label, pose, ground_truth_pose, velocity";

namespace {

// Blob helpers: decode straight from SQLite's buffer.
template <typename Decode>
auto decodeColumn(const Statement& row, int column, Decode decode) {
  size_t size = 0;
  const unsigned char* data = row.columnBlob(column, &size);
  return decode(data, size);
}

cv::Mat uncompressedColumn(const Statement& row, int column) {
  size_t size = 0;
  const unsigned char* data = row.columnBlob(column, &size);
  return size ? codec::uncompressData(data, size) : cv::Mat();
}

// Reads the Feature row into the node's words.
void readWords(Connection& c, Signature& node, bool descriptors) {
  Query q = c.query(descriptors
                        ? "SELECT word_ids, keypoints, points, descriptors FROM Feature WHERE node_id = ?"
                        : "SELECT word_ids, keypoints, points FROM Feature WHERE node_id = ?");
  q->bind(1, node.id());
  if (!q->step()) return;
  const std::vector<int> ids = decodeColumn(*q, 0, blob::decodeWordIds);
  if (ids.empty()) return;
  std::multimap<int, int> words;
  for (size_t i = 0; i < ids.size(); ++i) words.emplace_hint(words.end(), ids[i], static_cast<int>(i));
  const cv::Mat descriptorRows = descriptors ? decodeColumn(*q, 3, blob::decodeMatrix) : cv::Mat();
  try {
    node.setWords(words, decodeColumn(*q, 1, blob::decodeKeypoints),
                  decodeColumn(*q, 2, blob::decodePoints), descriptorRows);
  } catch (const std::invalid_argument& e) {
    throw FormatError(std::string("stored features are inconsistent: ") + e.what());
  }
}

// Which Data columns to read: fixed names, chosen by the load options. Order matters (see the
// schema): the small ones first, the images last.
std::string dataQuery(const LoadOptions& o, std::vector<std::string>* columns) {
  *columns = {"calibration", "scan_info", "cell_size", "view_point", "imu", "gps"};
  if (o.scan) columns->push_back("scan");
  if (o.userData) columns->push_back("user_data");
  if (o.grid) {
    for (const char* c : {"ground_cells", "obstacle_cells", "empty_cells"}) columns->push_back(c);
  }
  if (o.depthOrRight) columns->push_back("depth");
  if (o.image) columns->push_back("image");
  std::string sql = "SELECT ";
  for (size_t i = 0; i < columns->size(); ++i) sql += (i ? ", " : "") + (*columns)[i];
  return sql + " FROM Data WHERE id = ?";
}

void readSensorData(Connection& c, Signature& node, const LoadOptions& o) {
  std::vector<std::string> columns;
  Query q = c.query(dataQuery(o, &columns));
  q->bind(1, node.id());
  SensorData data;
  if (q->step()) {
    const auto column = [&columns](const char* name) {
      for (size_t i = 0; i < columns.size(); ++i)
        if (columns[i] == name) return static_cast<int>(i);
      return -1;
    };
    const auto bytes = [&](const char* name) {
      const int i = column(name);
      return i < 0 ? Bytes() : q->columnBytes(i);
    };
    std::vector<CameraModel> cameras;
    std::vector<StereoCameraModel> stereo;
    size_t size = 0;
    const unsigned char* calibration = q->columnBlob(0, &size);
    blob::decodeCalibration(calibration, size, &cameras, &stereo);
    if (!stereo.empty()) {
      data.setStereoImage(cv::Mat(), cv::Mat(), stereo);
    } else if (!cameras.empty()) {
      data.setRGBDImage(cv::Mat(), cv::Mat(), cameras);
    }
    // After the camera setters, which clear the compressed images.
    data.setCompressed(bytes("image"), bytes("depth"), bytes("scan"), bytes("user_data"));
    data.setLaserScanInfo(decodeColumn(*q, 1, blob::decodeScanInfo));
    if (o.grid && !q->isNull(2)) {
      LocalGrid grid;
      grid.cellSize = static_cast<float>(q->columnDouble(2));
      grid.viewPoint = decodeColumn(*q, 3, blob::decodeVector3f);
      grid.ground = uncompressedColumn(*q, column("ground_cells"));
      grid.obstacles = uncompressedColumn(*q, column("obstacle_cells"));
      grid.empty = uncompressedColumn(*q, column("empty_cells"));
      data.setLocalGrid(grid);
    }
    data.setIMU(decodeColumn(*q, 4, blob::decodeImu));
    data.setGPS(decodeColumn(*q, 5, blob::decodeGps));
  }
  data.setId(node.id());
  data.setStamp(node.stamp());
  data.setGroundTruth(node.getGroundTruthPose());
  node.setSensorData(data);
}

}  // namespace

Signature headerFromRow(const Statement& row) {
  Signature node(row.columnInt(0), row.columnInt(1), row.columnInt(2), row.columnDouble(3),
                 row.isNull(4) ? std::string() : row.columnText(4),
                 decodeColumn(row, 5, blob::decodeTransform), decodeColumn(row, 6, blob::decodeTransform));
  if (!row.isNull(7)) node.setVelocity(decodeColumn(row, 7, blob::decodeVelocity));
  node.setSaved(true);
  node.setModified(false);
  node.setLinksModified(false);
  return node;
}

std::optional<Signature> node(Connection& c, int id, const LoadOptions& options) {
  std::optional<Signature> node;
  {
    Query q = c.query(std::string("SELECT ") + kNodeColumns + " FROM Node WHERE id = ?");
    q->bind(1, id);
    if (!q->step()) return std::nullopt;
    node = headerFromRow(*q);
  }
  try {
    if (options.links) {
      for (const auto& entry : links(c, id)) node->addLink(entry.second);
    }
    if (options.words) readWords(c, *node, options.wordDescriptors);
    if (options.anySensorData()) readSensorData(c, *node, options);
  } catch (const FormatError& e) {
    throw DatabaseError(c.path() + ": node " + std::to_string(id) + " is damaged: " + e.what());
  }
  node->setSaved(true);
  node->setModified(false);
  node->setLinksModified(false);
  return node;
}

std::multimap<int, Link> links(Connection& c, int id) {
  std::multimap<int, Link> result;
  Query q = c.query("SELECT to_id, type, transform, information, user_data FROM Link WHERE from_id = ?");
  q->bind(1, id);
  while (q->step()) {
    const int to = q->columnInt(0);
    Link link(id, to, Link::typeFromInt(q->columnInt(1)), decodeColumn(*q, 2, blob::decodeTransform),
              decodeColumn(*q, 3, blob::decodeInformation), uncompressedColumn(*q, 4));
    result.emplace(to, std::move(link));
  }
  return result;
}

std::optional<StoredWord> word(Connection& c, int id) {
  Query q = c.query("SELECT descriptor FROM Word WHERE id = ?");
  q->bind(1, id);
  if (!q->step()) return std::nullopt;
  try {
    return StoredWord{id, decodeColumn(*q, 0, blob::decodeMatrix)};
  } catch (const FormatError& e) {
    throw DatabaseError(c.path() + ": word " + std::to_string(id) + " is damaged: " + e.what());
  }
}

std::optional<StoredStatistics> statistics(Connection& c, int nodeId) {
  Query q = c.query("SELECT stamp, data, wm_state FROM Statistics WHERE node_id = ?");
  q->bind(1, nodeId);
  if (!q->step()) return std::nullopt;
  StoredStatistics s;
  s.nodeId = nodeId;
  s.stamp = q->columnDouble(0);
  try {
    s.data = decodeColumn(*q, 1, blob::decodeStatistics);
    s.wmState = decodeColumn(*q, 2, blob::decodeIds);
  } catch (const FormatError& e) {
    throw DatabaseError(c.path() + ": statistics of node " + std::to_string(nodeId) +
                        " are damaged: " + e.what());
  }
  return s;
}

}  // namespace rtabmap::db::load

#include "NodeStore.h"

#include <sqlite3.h>

#include <chrono>
#include <type_traits>

#include "Blobs.h"
#include "Sqlite.h"
#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/db/Version.h"

namespace rtabmap::db::store {

namespace {

double now() {
  using namespace std::chrono;
  return duration<double>(system_clock::now().time_since_epoch()).count();
}

bool hasSensorData(const SensorData& d) {
  return !d.imageCompressed().empty() || !d.imageRaw().empty() ||
         !d.depthOrRightCompressed().empty() || !d.depthOrRightRaw().empty() ||
         !d.laserScanCompressed().empty() || !d.laserScanRaw().empty() ||
         !d.userDataCompressed().empty() || !d.userDataRaw().empty() ||
         !d.cameraModels().empty() || !d.stereoCameraModels().empty() ||
         !d.localGrid().isEmpty() || !d.imu().empty() || d.gps().stamp != 0.0;
}

// The compressed form of each part: the one given, else the raw part compressed here, on the
// writer thread, so that the caller's update never pays for an image encoder.
struct CompressedParts {
  Bytes image, depthOrRight, scan, userData;
};

CompressedParts compressedParts(const SensorData& data, const std::string& imageFormat) {
  CompressedParts parts{data.imageCompressed(), data.depthOrRightCompressed(),
                        data.laserScanCompressed(), data.userDataCompressed()};
  const bool missing = (parts.image.empty() && !data.imageRaw().empty()) ||
                       (parts.depthOrRight.empty() && !data.depthOrRightRaw().empty()) ||
                       (parts.scan.empty() && !data.laserScanRaw().empty()) ||
                       (parts.userData.empty() && !data.userDataRaw().empty());
  if (!missing) return parts;
  SensorData copy = data;
  copy.compress(imageFormat);
  if (parts.image.empty()) parts.image = copy.imageCompressed();
  if (parts.depthOrRight.empty()) parts.depthOrRight = copy.depthOrRightCompressed();
  if (parts.scan.empty()) parts.scan = copy.laserScanCompressed();
  if (parts.userData.empty()) parts.userData = copy.userDataCompressed();
  return parts;
}

Bytes compressedMat(const cv::Mat& m) { return m.empty() ? Bytes() : codec::compressData(m); }

void writeNodeRow(Connection& c, const Signature& s) {
  // Upsert, not REPLACE: REPLACE deletes then inserts, and an empty word list must keep the
  // stored count (see Database::saveNode).
  Query q = c.query(
      "INSERT INTO Node (id, map_id, weight, stamp, label, pose, ground_truth_pose, velocity, "
      "word_count, time_enter) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?) "
      "ON CONFLICT(id) DO UPDATE SET map_id = excluded.map_id, weight = excluded.weight, "
      "stamp = excluded.stamp, label = excluded.label, pose = excluded.pose, "
      "ground_truth_pose = excluded.ground_truth_pose, velocity = excluded.velocity, "
      "word_count = CASE WHEN excluded.word_count > 0 THEN excluded.word_count "
      "ELSE Node.word_count END, time_enter = excluded.time_enter");
  const Bytes pose = blob::encodeTransform(s.getPose());
  const Bytes groundTruth = blob::encodeTransform(s.getGroundTruthPose());
  const Bytes velocity = s.getVelocity() ? blob::encodeVelocity(*s.getVelocity()) : Bytes();
  q->bind(1, s.id()).bind(2, s.mapId()).bind(3, s.weight()).bind(4, s.stamp());
  if (s.label().empty()) q->bindNull(5); else q->bind(5, s.label());
  q->bindBlob(6, pose).bindBlob(7, groundTruth).bindBlob(8, velocity);
  q->bind(9, static_cast<int>(s.getWords().size())).bind(10, now());
  q->run();
}

void writeData(Connection& c, int id, const SensorData& data, const std::string& imageFormat) {
  if (!hasSensorData(data)) {
    // Keep what is stored; create the (empty) row of a new node so every node has one.
    Query q = c.query("INSERT OR IGNORE INTO Data (id) VALUES (?)");
    q->bind(1, id);
    q->run();
    return;
  }
  const CompressedParts parts = compressedParts(data, imageFormat);
  const LocalGrid& grid = data.localGrid();
  const Bytes calibration = blob::encodeCalibration(data.cameraModels(), data.stereoCameraModels());
  const SensorData::ScanInfo scanInfo = data.laserScanInfo();
  const Bytes scanInfoBytes =
      (parts.scan.empty() && scanInfo.format == LaserScan::kUnknown) ? Bytes() : blob::encodeScanInfo(scanInfo);
  const Bytes viewPoint = grid.isEmpty() ? Bytes() : blob::encodeVector3f(grid.viewPoint);
  const Bytes imu = blob::encodeImu(data.imu());
  const Bytes gps = blob::encodeGps(data.gps());
  const Bytes ground = compressedMat(grid.ground);
  const Bytes obstacles = compressedMat(grid.obstacles);
  const Bytes empty = compressedMat(grid.empty);

  Query q = c.query(
      "INSERT OR REPLACE INTO Data (id, calibration, scan_info, cell_size, view_point, imu, gps, "
      "scan, user_data, ground_cells, obstacle_cells, empty_cells, depth, image) "
      "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  q->bind(1, id).bindBlob(2, calibration).bindBlob(3, scanInfoBytes);
  if (grid.isEmpty()) q->bindNull(4); else q->bind(4, static_cast<double>(grid.cellSize));
  q->bindBlob(5, viewPoint).bindBlob(6, imu).bindBlob(7, gps).bindBlob(8, parts.scan);
  q->bindBlob(9, parts.userData).bindBlob(10, ground).bindBlob(11, obstacles).bindBlob(12, empty);
  q->bindBlob(13, parts.depthOrRight).bindBlob(14, parts.image);
  q->run();
}

void writeFeatures(Connection& c, const Signature& s) {
  if (s.getWords().empty()) {
    Query q = c.query("INSERT OR IGNORE INTO Feature (node_id) VALUES (?)");
    q->bind(1, s.id());
    q->run();
    return;
  }
  const Bytes wordIds = blob::encodeWordIds(s.wordIdPerKeypoint());
  const Bytes keypoints = blob::encodeKeypoints(s.getWordsKpts());
  const Bytes points = blob::encodePoints(s.getWords3());
  const Bytes descriptors = blob::encodeMatrix(s.getWordsDescriptors());
  Query q = c.query(
      "INSERT OR REPLACE INTO Feature (node_id, word_ids, keypoints, points, descriptors) "
      "VALUES (?, ?, ?, ?, ?)");
  q->bind(1, s.id()).bindBlob(2, wordIds).bindBlob(3, keypoints).bindBlob(4, points).bindBlob(5, descriptors);
  q->run();
}

void insertLink(Connection& c, const Link& link) {
  Query q = c.query(
      "INSERT OR REPLACE INTO Link (from_id, to_id, type, transform, information, user_data) "
      "VALUES (?, ?, ?, ?, ?, ?)");
  const Bytes transform = blob::encodeTransform(link.transform());
  const Bytes information = blob::encodeInformation(link.infMatrix());
  const Bytes userData = compressedMat(link.userData());
  q->bind(1, link.from()).bind(2, link.to()).bind(3, static_cast<int>(link.type()));
  q->bindBlob(4, transform).bindBlob(5, information).bindBlob(6, userData);
  q->run();
}

void writeLinks(Connection& c, const Signature& s) {
  {
    Query q = c.query("DELETE FROM Link WHERE from_id = ?");
    q->bind(1, s.id());
    q->run();
  }
  for (const auto& entry : s.getLinks()) {
    if (entry.second.type() != Link::kTemporary) insertLink(c, entry.second);
  }
}

void writeWords(Connection& c, const std::vector<StoredWord>& words) {
  for (const StoredWord& word : words) {
    const Bytes descriptor = blob::encodeMatrix(word.descriptor);
    Query q = c.query("INSERT OR REPLACE INTO Word (id, descriptor) VALUES (?, ?)");
    q->bind(1, word.id).bindBlob(2, descriptor);
    q->run();
  }
}

void deleteLink(Connection& c, int from, int to, Link::Type type) {
  if (type == Link::kUndef) {
    Query q = c.query("DELETE FROM Link WHERE from_id = ? AND to_id = ?");
    q->bind(1, from).bind(2, to);
    q->run();
  } else {
    Query q = c.query("DELETE FROM Link WHERE from_id = ? AND to_id = ? AND type = ?");
    q->bind(1, from).bind(2, to).bind(3, static_cast<int>(type));
    q->run();
  }
}

// A link is also stored from its other end, unless it has none (self links: pose prior,
// gravity) or the other end is a landmark (negative id), which is not a node.
bool storedFromBothEnds(int from, int to) { return to != from && to > 0; }

void updateNode(Connection& c, const NodeUpdate& u) {
  if (u.weight) {
    Query q = c.query("UPDATE Node SET weight = ? WHERE id = ?");
    q->bind(1, *u.weight).bind(2, u.id);
    q->run();
  }
  if (u.label) {
    Query q = c.query("UPDATE Node SET label = ? WHERE id = ?");
    if (u.label->empty()) q->bindNull(1); else q->bind(1, *u.label);
    q->bind(2, u.id);
    q->run();
  }
  if (u.pose) {
    const Bytes pose = blob::encodeTransform(*u.pose);
    Query q = c.query("UPDATE Node SET pose = ? WHERE id = ?");
    q->bindBlob(1, pose).bind(2, u.id);
    q->run();
  }
}

void writeStatistics(Connection& c, const StoredStatistics& s) {
  const Bytes data = blob::encodeStatistics(s.data);
  const Bytes wmState = blob::encodeIds(s.wmState);
  Query q = c.query("INSERT OR REPLACE INTO Statistics (node_id, stamp, data, wm_state) VALUES (?, ?, ?, ?)");
  q->bind(1, s.nodeId).bind(2, s.stamp).bindBlob(3, data).bindBlob(4, wmState);
  q->run();
}

// One function per operation type, selected by std::visit.
struct Applier {
  Connection& c;
  const std::string& imageFormat;

  void operator()(const SaveNodeOp& op) const {
    writeNodeRow(c, op.node);
    writeData(c, op.node.id(), op.node.sensorData(), imageFormat);
    writeFeatures(c, op.node);
    writeLinks(c, op.node);
    writeWords(c, op.words);
  }
  void operator()(const SaveWordsOp& op) const { writeWords(c, op.words); }
  void operator()(const SaveLinkOp& op) const {
    insertLink(c, op.link);
    if (storedFromBothEnds(op.link.from(), op.link.to())) insertLink(c, op.link.inverse());
  }
  void operator()(const RemoveLinkOp& op) const {
    deleteLink(c, op.from, op.to, op.type);
    if (storedFromBothEnds(op.from, op.to)) deleteLink(c, op.to, op.from, op.type);
  }
  void operator()(const UpdateNodeOp& op) const { updateNode(c, op.update); }
  void operator()(const SaveStatisticsOp& op) const { writeStatistics(c, op.statistics); }
  void operator()(const SessionParametersOp& op) const {
    Query q = c.query("UPDATE Session SET parameters = ? WHERE id = ?");
    q->bind(1, op.parameters).bind(2, op.sessionId);
    q->run();
  }
  void operator()(const EndSessionOp& op) const {
    Query q = c.query("UPDATE Session SET end_time = ? WHERE id = ?");
    q->bind(1, op.endTime).bind(2, op.sessionId);
    q->run();
  }
};

}  // namespace

void apply(Connection& connection, const Operation& operation, const std::string& imageFormat) {
  std::visit(Applier{connection, imageFormat}, operation.op);
}

int insertSession(Connection& connection, int mapId, const std::string& parameters) {
  Query q = connection.query(
      "INSERT INTO Session (map_id, start_time, rtabmap_ros_version, parameters) VALUES (?, ?, ?, ?)");
  q->bind(1, mapId).bind(2, now()).bind(3, std::string(kRtabmapRosVersion)).bind(4, parameters);
  q->run();
  return static_cast<int>(sqlite3_last_insert_rowid(connection.handle()));
}

}  // namespace rtabmap::db::store

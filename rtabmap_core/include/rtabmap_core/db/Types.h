#pragma once
// Plain records the long-term memory reads and writes besides Signature and Link.
#include <opencv2/core/mat.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap::db {

// A visual word of the dictionary as stored: its id and its descriptor (1 x D row, the type
// of the feature descriptor: CV_8U for binary ORB/BRIEF, CV_32F for SIFT...).
struct StoredWord {
  int id = 0;
  cv::Mat descriptor;
};

// Which parts of a node to load. Sensor data comes back compressed (SensorData's compressed
// form), except the local grid which SensorData only holds raw.
struct LoadOptions {
  bool links = true;
  bool words = true;            // word ids, 2D keypoints, 3D points
  bool wordDescriptors = true;  // the per-keypoint descriptors (the bulk of the words)
  bool image = true;            // RGB or left image
  bool depthOrRight = true;
  bool scan = true;
  bool userData = true;
  bool grid = true;
  // Camera models, IMU and GPS come with any sensor part (they are a few hundred bytes).

  static LoadOptions all() { return LoadOptions(); }
  // Identity, weight, poses, label and links: what graph algorithms need.
  static LoadOptions withoutSensorData();
  // Only the node row: no links, words or sensor data.
  static LoadOptions nodeOnly();
  bool anySensorData() const { return image || depthOrRight || scan || userData || grid; }
};

// Changes to a node already saved (memory management updates weights; the user sets labels;
// graph optimisation may rewrite poses). Unset fields keep their stored value.
struct NodeUpdate {
  int id = 0;
  std::optional<int> weight;
  std::optional<std::string> label;  // "" removes the label
  std::optional<Transform> pose;
};

// One session: every open for writing starts a new one, with its own map id.
struct SessionInfo {
  int id = 0;
  int mapId = 0;            // first map id of the session (a session may create more)
  double startTime = 0.0;   // unix time
  double endTime = 0.0;     // 0 if the session did not close cleanly (or is still open)
  std::string rtabmapRosVersion;
  std::string parameters;   // the params area's serialised ParametersMap
};

// The statistics of the update that created a node (slam/Statistics data and WM state).
struct StoredStatistics {
  int nodeId = 0;
  double stamp = 0.0;
  std::map<std::string, float> data;
  std::vector<int> wmState;
};

// One transaction committed by the background writer (Database::Options::onCommitted).
struct CommitInfo {
  std::vector<int> nodeIds;   // nodes made durable, in the order they were saved (may be empty)
  uint64_t ticket = 0;        // operations 1..ticket are now durable
  size_t operations = 0;      // operations in the transaction
  double writeSeconds = 0.0;  // writer time for the transaction: statements, compression, commit
};

// State of the background writer.
struct WriterStatus {
  bool failed = false;        // the writer stopped on an error; see `error`
  std::string error;
  int lastDurableNodeId = 0;  // the last node whose transaction committed (0: none yet)
  uint64_t durableTicket = 0; // operations 1..durableTicket are committed
  uint64_t queuedTicket = 0;  // ticket of the last operation queued
  size_t pendingOperations = 0;
  size_t pendingNodes = 0;
};

struct SessionSummary {
  SessionInfo info;
  int64_t nodes = 0;  // nodes whose map id belongs to this session
};

// Counts and sizes of a database (rtabmap-info).
struct DatabaseSummary {
  std::string path;
  int schemaVersion = 0;
  std::string createdBy;      // rtabmap_ros version that created the file
  std::string lastWrittenBy;  // rtabmap_ros version that last opened it for writing
  std::vector<SessionSummary> sessions;
  std::map<int, int64_t> nodesPerMap;
  int64_t nodes = 0;
  int64_t intermediateNodes = 0;  // of `nodes`: weight -1 (Rtabmap/CreateIntermediateNodes)
  std::map<int, int64_t> linksPerType;  // Link::Type -> count of constraints (each once)
  int64_t links = 0;
  int64_t words = 0;
  int64_t features = 0;  // node-word features (keypoints of all nodes)
  int64_t statistics = 0;
  int lastNodeId = 0;
  int lastWordId = 0;
  int64_t fileBytes = 0;  // database file + its WAL
  int64_t pageSize = 0;
  int64_t pageCount = 0;
};

// What checkConsistency() found. A database written only through Database is always
// consistent; a non-zero count means an outside edit or a bug.
struct ConsistencyReport {
  int64_t nodesWithoutData = 0;
  int64_t nodesWithoutFeatures = 0;
  int64_t dataWithoutNode = 0;     // sensor data rows of no node
  int64_t featuresWithoutNode = 0; // feature rows of no node
  int64_t featureCountMismatch = 0;// feature rows whose blobs disagree with Node.word_count
  int64_t missingWords = 0;        // features whose word id is not in the Word table (full only)
  std::string integrity = "ok";    // PRAGMA quick_check (full only)
  bool ok() const {
    return nodesWithoutData == 0 && nodesWithoutFeatures == 0 && dataWithoutNode == 0 &&
           featuresWithoutNode == 0 && featureCountMismatch == 0 && integrity == "ok";
  }
  std::string toString() const;
};

}  // namespace rtabmap::db

#pragma once
// A node of the map (T-RO 2013 "signature" / "location"): what the robot perceived at one place
// and how it connects to the rest of the graph. It holds
//  - identity: id (unique over all sessions), map id (the session's map), stamp, label;
//  - the weight that rehearsal increases and memory management reads (T-RO 2013, 3.1); -1
//    marks an intermediate node (Rtabmap/CreateIntermediateNodes: a pose of the trajectory
//    between two updates, no visual words, never a loop-closure candidate), as in the original;
//  - poses: odometry pose, optional ground truth, optional velocity;
//  - its visual words (bag-of-words of the image): word ids with, per keypoint, the 2D
//    keypoint, its 3D point in the robot base frame (NaN if unknown) and its descriptor;
//  - its SensorData (images, scan, local grid; raw and/or compressed);
//  - its links to other nodes, keyed by the other node's id.
//
// This is a data type: the algorithms that create, merge and transfer nodes belong to the
// memory-management code (STM / WM / LTM).
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap {

class Signature {
 public:
  // Linear (vx vy vz) and angular (vroll vpitch vyaw) velocity in the base frame.
  using Velocity = std::array<float, 6>;

  Signature() = default;
  explicit Signature(int id, int mapId = 0, int weight = 0, double stamp = 0.0,
                     const std::string& label = std::string(), const Transform& pose = Transform(),
                     const Transform& groundTruthPose = Transform(),
                     const SensorData& sensorData = SensorData());
  // A node created from a sensor frame: id and stamp come from the data, pose from its odometry.
  explicit Signature(const SensorData& data);

  // --- identity and memory-management state ---
  int id() const { return id_; }
  int mapId() const { return mapId_; }
  int weight() const { return weight_; }
  static constexpr int kIntermediateWeight = -1;
  bool isIntermediate() const { return weight_ == kIntermediateWeight; }
  double stamp() const { return stamp_; }
  const std::string& label() const { return label_; }
  void setId(int id);
  void setMapId(int mapId) { mapId_ = mapId; modified_ = true; }
  void setWeight(int weight);
  void setStamp(double stamp) { stamp_ = stamp; modified_ = true; }
  void setLabel(const std::string& label);

  // --- poses ---
  const Transform& getPose() const { return pose_; }
  const Transform& getGroundTruthPose() const { return groundTruthPose_; }
  const std::optional<Velocity>& getVelocity() const { return velocity_; }
  void setPose(const Transform& pose);
  void setGroundTruthPose(const Transform& pose) { groundTruthPose_ = pose; modified_ = true; }
  void setVelocity(const Velocity& velocity) { velocity_ = velocity; modified_ = true; }
  void clearVelocity() { velocity_.reset(); modified_ = true; }

  // --- visual words ---
  // words: word id -> keypoint index. Each index in [0, N) appears exactly once (a word id may
  // repeat: two keypoints quantised to the same word). keypoints, points3D and descriptors are
  // either empty or have N entries (descriptors: N rows). Throws std::invalid_argument
  // otherwise.
  void setWords(const std::multimap<int, int>& words, const std::vector<cv::KeyPoint>& keypoints,
                const std::vector<cv::Point3f>& points3D, const cv::Mat& descriptors);
  const std::multimap<int, int>& getWords() const { return words_; }
  const std::vector<cv::KeyPoint>& getWordsKpts() const { return wordsKpts_; }
  const std::vector<cv::Point3f>& getWords3() const { return words3_; }
  const cv::Mat& getWordsDescriptors() const { return wordsDescriptors_; }
  // Word id of each keypoint index (the inverse of getWords()); empty if no words.
  std::vector<int> wordIdPerKeypoint() const;
  // Replaces a word id (vocabulary merge), keeping the keypoint indices.
  void changeWordsRef(int oldWordId, int newWordId);
  void removeAllWords();
  bool isWordsEmpty() const { return words_.empty(); }

  // A node whose image gave too few words to take part in loop-closure detection (Kp/BadSignRatio
  // in the memory update, or no words at all, e.g. a laser-only node).
  bool isBadSignature() const { return badSignature_ || words_.empty(); }
  void setBadSignature(bool bad) { badSignature_ = bad; }

  // --- sensor data ---
  const SensorData& sensorData() const { return sensorData_; }
  SensorData& sensorData() { return sensorData_; }
  void setSensorData(const SensorData& data) { sensorData_ = data; modified_ = true; }

  // --- links (one per other node and type) ---
  // Adds a link that starts at this node (link.from() == id()); a link of the same type to the
  // same node is replaced. Throws std::invalid_argument if link.from() != id().
  void addLink(const Link& link);
  // Removes links to `to` of this type (kUndef: of any type). Returns how many were removed.
  int removeLink(int to, Link::Type type = Link::kUndef);
  // Removes every link of this type (kUndef: all links).
  int removeLinks(Link::Type type = Link::kUndef);
  bool hasLink(int to, Link::Type type = Link::kUndef) const;
  // The link to `to` of this type (kUndef: the first of any type), or nullptr.
  const Link* link(int to, Link::Type type = Link::kUndef) const;
  const std::multimap<int, Link>& getLinks() const { return links_; }
  // Links to landmarks (negative ids) and self links (pose prior, gravity) excluded.
  std::map<int, Link> getNeighborLinks() const;
  // Renames the other end of links (node merge): links to oldId now go to newId.
  void changeLinkIds(int oldId, int newId);

  // --- persistence flags (read by the long-term memory and memory management) ---
  bool isSaved() const { return saved_; }
  bool isModified() const { return modified_; }
  bool isLinksModified() const { return linksModified_; }
  bool isEnabled() const { return enabled_; }
  void setSaved(bool saved) { saved_ = saved; }
  void setModified(bool modified) { modified_ = modified; }
  void setLinksModified(bool modified) { linksModified_ = modified; }
  void setEnabled(bool enabled) { enabled_ = enabled; }

  // Approximate bytes held in memory (words, descriptors, sensor data).
  size_t memoryUsed() const;

 private:
  int id_ = 0;
  int mapId_ = 0;
  int weight_ = 0;
  double stamp_ = 0.0;
  std::string label_;
  Transform pose_;
  Transform groundTruthPose_;
  std::optional<Velocity> velocity_;

  std::multimap<int, int> words_;
  std::vector<cv::KeyPoint> wordsKpts_;
  std::vector<cv::Point3f> words3_;
  cv::Mat wordsDescriptors_;
  bool badSignature_ = false;

  SensorData sensorData_;
  std::multimap<int, Link> links_;

  bool saved_ = false;
  bool modified_ = true;
  bool linksModified_ = true;
  bool enabled_ = false;
};

// Keeps both endpoints consistent: adds `link` to `from` (link.from() == from.id()) and its
// inverse to `to` (link.to() == to.id()). Throws std::invalid_argument on an id mismatch.
void addLinkBetween(Signature& from, Signature& to, const Link& link);
// Removes the links of this type (kUndef: all) between the two nodes, on both ends.
void removeLinkBetween(Signature& a, Signature& b, Link::Type type = Link::kUndef);

// The node's laser scan, uncompressed into its sensor data when only the compressed form is
// there (registration and proximity detection need the points). Empty, with *problem set when
// given, if it cannot be uncompressed.
const LaserScan& scanOf(Signature& node, std::string* problem = nullptr);

}  // namespace rtabmap

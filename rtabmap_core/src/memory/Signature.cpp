#include "rtabmap_core/memory/Signature.h"

#include <stdexcept>
#include <string>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {

Signature::Signature(int id, int mapId, int weight, double stamp, const std::string& label,
                     const Transform& pose, const Transform& groundTruthPose,
                     const SensorData& sensorData)
    : id_(id), mapId_(mapId), weight_(weight), stamp_(stamp), label_(label), pose_(pose),
      groundTruthPose_(groundTruthPose), sensorData_(sensorData) {
  sensorData_.setId(id);
}

Signature::Signature(const SensorData& data)
    : id_(data.id()), stamp_(data.stamp()), pose_(data.odomPose()),
      groundTruthPose_(data.groundTruth()), sensorData_(data) {}

void Signature::setId(int id) {
  id_ = id;
  sensorData_.setId(id);
  modified_ = true;
}

void Signature::setWeight(int weight) {
  if (weight != weight_) modified_ = true;
  weight_ = weight;
}

void Signature::setLabel(const std::string& label) {
  if (label != label_) modified_ = true;
  label_ = label;
}

void Signature::setPose(const Transform& pose) {
  pose_ = pose;
  modified_ = true;
}

void Signature::setWords(const std::multimap<int, int>& words,
                         const std::vector<cv::KeyPoint>& keypoints,
                         const std::vector<cv::Point3f>& points3D, const cv::Mat& descriptors) {
  const size_t n = words.size();
  const auto mismatch = [&](const char* what, size_t count) {
    throw std::invalid_argument("Signature " + std::to_string(id_) + ": " + std::to_string(n) +
                                " words but " + std::to_string(count) + " " + what);
  };
  if (!keypoints.empty() && keypoints.size() != n) mismatch("keypoints", keypoints.size());
  if (!points3D.empty() && points3D.size() != n) mismatch("3D points", points3D.size());
  if (!descriptors.empty() && static_cast<size_t>(descriptors.rows) != n) {
    mismatch("descriptor rows", static_cast<size_t>(descriptors.rows));
  }
  // Every keypoint index exactly once: the database stores the word id per keypoint.
  std::vector<bool> seen(n, false);
  for (const auto& [wordId, index] : words) {
    if (index < 0 || static_cast<size_t>(index) >= n || seen[index]) {
      throw std::invalid_argument("Signature " + std::to_string(id_) + ": word " +
                                  std::to_string(wordId) + " has keypoint index " +
                                  std::to_string(index) +
                                  " (each index in [0, " + std::to_string(n) +
                                  ") must appear exactly once)");
    }
    seen[index] = true;
  }
  words_ = words;
  wordsKpts_ = keypoints;
  words3_ = points3D;
  wordsDescriptors_ = descriptors;
  modified_ = true;
}

std::vector<int> Signature::wordIdPerKeypoint() const {
  std::vector<int> ids(words_.size(), 0);
  for (const auto& [wordId, index] : words_) ids[index] = wordId;
  return ids;
}

void Signature::changeWordsRef(int oldWordId, int newWordId) {
  auto range = words_.equal_range(oldWordId);
  if (range.first == range.second) return;
  std::vector<int> indices;
  for (auto it = range.first; it != range.second; ++it) indices.push_back(it->second);
  words_.erase(range.first, range.second);
  for (int index : indices) words_.emplace(newWordId, index);
  modified_ = true;
}

void Signature::removeAllWords() {
  words_.clear();
  wordsKpts_.clear();
  words3_.clear();
  wordsDescriptors_ = cv::Mat();
  modified_ = true;
}

void Signature::addLink(const Link& link) {
  if (link.from() != id_) {
    throw std::invalid_argument("Signature " + std::to_string(id_) + ": cannot add link " +
                                std::to_string(link.from()) + "->" + std::to_string(link.to()) +
                                " that does not start here");
  }
  removeLink(link.to(), link.type());
  links_.emplace(link.to(), link);
  linksModified_ = true;
}

int Signature::removeLink(int to, Link::Type type) {
  int removed = 0;
  auto range = links_.equal_range(to);
  for (auto it = range.first; it != range.second;) {
    if (type == Link::kUndef || it->second.type() == type) {
      it = links_.erase(it);
      ++removed;
    } else {
      ++it;
    }
  }
  if (removed) linksModified_ = true;
  return removed;
}

int Signature::removeLinks(Link::Type type) {
  int removed = 0;
  for (auto it = links_.begin(); it != links_.end();) {
    if (type == Link::kUndef || it->second.type() == type) {
      it = links_.erase(it);
      ++removed;
    } else {
      ++it;
    }
  }
  if (removed) linksModified_ = true;
  return removed;
}

bool Signature::hasLink(int to, Link::Type type) const { return link(to, type) != nullptr; }

const Link* Signature::link(int to, Link::Type type) const {
  auto range = links_.equal_range(to);
  for (auto it = range.first; it != range.second; ++it) {
    if (type == Link::kUndef || it->second.type() == type) return &it->second;
  }
  return nullptr;
}

std::map<int, Link> Signature::getNeighborLinks() const {
  std::map<int, Link> neighbors;
  for (const auto& [to, link] : links_) {
    if (to > 0 && to != id_) neighbors.emplace(to, link);
  }
  return neighbors;
}

void Signature::changeLinkIds(int oldId, int newId) {
  auto range = links_.equal_range(oldId);
  std::vector<Link> moved;
  for (auto it = range.first; it != range.second; ++it) moved.push_back(it->second);
  if (moved.empty()) return;
  links_.erase(range.first, range.second);
  for (Link& link : moved) {
    link.setTo(newId);
    addLink(link);
  }
}

size_t Signature::memoryUsed() const {
  size_t bytes = sizeof(Signature);
  bytes += words_.size() * (sizeof(int) * 2 + 32);  // map node overhead, roughly
  bytes += wordsKpts_.size() * sizeof(cv::KeyPoint);
  bytes += words3_.size() * sizeof(cv::Point3f);
  bytes += wordsDescriptors_.total() * wordsDescriptors_.elemSize();
  bytes += links_.size() * (sizeof(Link) + 32);
  bytes += sensorData_.memoryUsed();
  return bytes;
}

void addLinkBetween(Signature& from, Signature& to, const Link& link) {
  if (link.from() != from.id() || link.to() != to.id()) {
    throw std::invalid_argument("link " + std::to_string(link.from()) + "->" +
                                std::to_string(link.to()) + " does not join nodes " +
                                std::to_string(from.id()) + " and " + std::to_string(to.id()));
  }
  from.addLink(link);
  if (&from != &to) to.addLink(link.inverse());
}

void removeLinkBetween(Signature& a, Signature& b, Link::Type type) {
  a.removeLink(b.id(), type);
  b.removeLink(a.id(), type);
}

const LaserScan& scanOf(Signature& node, std::string* problem) {
  SensorData& data = node.sensorData();
  if (data.laserScanRaw().empty() && !data.laserScanCompressed().empty()) {
    try {
      data.uncompress(false, false, true, false);
    } catch (const Error& e) {
      if (problem) *problem = std::string("its laser scan cannot be uncompressed: ") + e.what();
    }
  }
  return data.laserScanRaw();
}

}  // namespace rtabmap

#include "Overlay.h"

#include <algorithm>

namespace rtabmap::db {

namespace {

// The link as stored from node `id` (the link itself or its inverse).
Link fromEnd(const Link& link, int id) { return link.from() == id ? link : link.inverse(); }

void eraseLinks(std::multimap<int, Link>& links, int other, Link::Type type) {
  auto range = links.equal_range(other);
  for (auto it = range.first; it != range.second;) {
    it = (type == Link::kUndef || it->second.type() == type) ? links.erase(it) : std::next(it);
  }
}

}  // namespace

const SaveNodeOp* Overlay::latestSave(int id, size_t* after) const {
  for (size_t i = queued_.size(); i-- > 0;) {
    const auto* save = std::get_if<SaveNodeOp>(&queued_[i]->op);
    if (save && save->node.id() == id) {
      *after = i + 1;
      return save;
    }
  }
  *after = 0;
  return nullptr;
}

void Overlay::applyNodeUpdates(Signature& node, size_t after) const {
  for (size_t i = after; i < queued_.size(); ++i) {
    const auto* update = std::get_if<UpdateNodeOp>(&queued_[i]->op);
    if (!update || update->update.id != node.id()) continue;
    if (update->update.weight) node.setWeight(*update->update.weight);
    if (update->update.label) node.setLabel(*update->update.label);
    if (update->update.pose) node.setPose(*update->update.pose);
  }
}

void Overlay::applyLinkChanges(int id, std::multimap<int, Link>& links, size_t after) const {
  for (size_t i = after; i < queued_.size(); ++i) {
    if (const auto* save = std::get_if<SaveLinkOp>(&queued_[i]->op)) {
      const Link& link = save->link;
      // Self and landmark links are stored only from their start (see NodeStore).
      if (link.from() == id || (link.to() == id && link.from() != id && id > 0)) {
        const Link stored = fromEnd(link, id);
        eraseLinks(links, stored.to(), stored.type());
        links.emplace(stored.to(), stored);
      }
    } else if (const auto* remove = std::get_if<RemoveLinkOp>(&queued_[i]->op)) {
      if (remove->from == id) eraseLinks(links, remove->to, remove->type);
      if (remove->to == id && remove->from != id) eraseLinks(links, remove->from, remove->type);
    }
  }
}

std::optional<StoredWord> Overlay::word(int id) const {
  for (size_t i = queued_.size(); i-- > 0;) {
    const std::vector<StoredWord>* words = nullptr;
    if (const auto* save = std::get_if<SaveNodeOp>(&queued_[i]->op)) words = &save->words;
    if (const auto* save = std::get_if<SaveWordsOp>(&queued_[i]->op)) words = &save->words;
    if (!words) continue;
    for (auto it = words->rbegin(); it != words->rend(); ++it) {
      if (it->id == id) return *it;
    }
  }
  return std::nullopt;
}

std::optional<StoredStatistics> Overlay::statistics(int nodeId) const {
  for (size_t i = queued_.size(); i-- > 0;) {
    const auto* save = std::get_if<SaveStatisticsOp>(&queued_[i]->op);
    if (save && save->statistics.nodeId == nodeId) return save->statistics;
  }
  return std::nullopt;
}

int Overlay::maxNodeId() const {
  int id = 0;
  for (const OperationPtr& op : queued_) {
    if (const auto* save = std::get_if<SaveNodeOp>(&op->op)) id = std::max(id, save->node.id());
  }
  return id;
}

int Overlay::maxWordId() const {
  int id = 0;
  for (const OperationPtr& op : queued_) {
    const std::vector<StoredWord>* words = nullptr;
    if (const auto* save = std::get_if<SaveNodeOp>(&op->op)) words = &save->words;
    if (const auto* save = std::get_if<SaveWordsOp>(&op->op)) words = &save->words;
    if (!words) continue;
    for (const StoredWord& w : *words) id = std::max(id, w.id);
  }
  return id;
}

int Overlay::maxMapId() const {
  int mapId = -1;
  for (const OperationPtr& op : queued_) {
    if (const auto* save = std::get_if<SaveNodeOp>(&op->op)) mapId = std::max(mapId, save->node.mapId());
  }
  return mapId;
}

Signature filteredCopy(const Signature& node, const LoadOptions& o) {
  Signature copy = node;
  if (!o.links) copy.removeLinks();
  copy.removeLinks(Link::kTemporary);  // never saved, so never loaded
  if (!o.words) {
    copy.removeAllWords();
  } else if (!o.wordDescriptors && !copy.getWordsDescriptors().empty()) {
    copy.setWords(node.getWords(), node.getWordsKpts(), node.getWords3(), cv::Mat());
  }
  const SensorData& in = node.sensorData();
  SensorData out;
  if (o.anySensorData()) {
    out = in;
    const cv::Mat image = o.image ? in.imageRaw() : cv::Mat();
    const cv::Mat depth = o.depthOrRight ? in.depthOrRightRaw() : cv::Mat();
    if (in.isStereo()) {
      out.setStereoImage(image, depth, in.stereoCameraModels());
    } else {
      out.setRGBDImage(image, depth, in.cameraModels());
    }
    out.setCompressed(o.image ? in.imageCompressed() : Bytes(),
                      o.depthOrRight ? in.depthOrRightCompressed() : Bytes(),
                      o.scan ? in.laserScanCompressed() : Bytes(),
                      o.userData ? in.userDataCompressed() : Bytes());
    out.setLaserScanInfo(in.laserScanInfo());
    if (!o.scan) out.setLaserScan(LaserScan());
    if (!o.userData) out.setUserData(cv::Mat());
    if (!o.grid) out.setLocalGrid(LocalGrid());
  }
  out.setId(node.id());
  out.setStamp(node.stamp());
  out.setGroundTruth(node.getGroundTruthPose());
  copy.setSensorData(out);
  copy.setSaved(true);
  copy.setModified(false);
  copy.setLinksModified(false);
  return copy;
}

}  // namespace rtabmap::db

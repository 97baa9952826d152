#include "VisualLocalMap.h"

#include <algorithm>
#include <tuple>
#include <vector>

namespace rtabmap::odometry_detail {

void VisualLocalMap::clear() {
  points_.clear();
  keyFrames_.clear();
  nextId_ = 1;
  nextKeyFrameId_ = 1;
  dirty_ = true;
}

const VisualFrame& VisualLocalMap::asFrame() const {
  if (!dirty_) return frame_;
  frame_ = VisualFrame();
  frame_.points3D.reserve(points_.size());
  frame_.ids.reserve(points_.size());
  if (!points_.empty()) {
    const cv::Mat& first = points_.begin()->second.descriptor;
    frame_.descriptors.create(static_cast<int>(points_.size()), first.cols, first.type());
  }
  int row = 0;
  for (const auto& [id, p] : points_) {
    frame_.points3D.push_back(p.position);
    frame_.ids.push_back(id);
    p.descriptor.copyTo(frame_.descriptors.row(row++));
  }
  dirty_ = false;
  return frame_;
}

int VisualLocalMap::addPoint(const cv::Point3f& position, const cv::Mat& descriptor, int frame) {
  Point p;
  p.position = position;
  p.descriptor = descriptor.clone();
  p.lastSeen = frame;
  p.observations = 1;
  const int id = nextId_++;
  points_.emplace(id, std::move(p));
  dirty_ = true;
  return id;
}

void VisualLocalMap::observe(int id, int frame, const cv::Mat& descriptor) {
  auto it = points_.find(id);
  if (it == points_.end()) return;
  it->second.lastSeen = frame;
  ++it->second.observations;
  if (!descriptor.empty()) {
    descriptor.copyTo(it->second.descriptor);
    dirty_ = true;
  }
}

void VisualLocalMap::addKeyFrame(KeyFrame keyFrame, int maxFrames) {
  keyFrame.id = nextKeyFrameId_++;
  keyFrames_.push_back(std::move(keyFrame));
  while (maxFrames > 0 && static_cast<int>(keyFrames_.size()) > maxFrames) keyFrames_.pop_front();
}

void VisualLocalMap::trim(size_t maxSize, const std::unordered_set<int>& keep) {
  if (maxSize > 0 && points_.size() > maxSize) {
    // Removal order: points outside `keep` first, then the longest unseen, then the least
    // observed (a new point of this frame goes before one matched again). `keep` only
    // postpones removal: the size limit is a hard one.
    std::vector<std::tuple<bool, int, int, int>> order;  // (kept, lastSeen, observations, id)
    order.reserve(points_.size());
    for (const auto& [id, p] : points_) order.emplace_back(keep.count(id) > 0, p.lastSeen, p.observations, id);
    std::sort(order.begin(), order.end());
    const size_t excess = points_.size() - maxSize;
    for (size_t i = 0; i < excess; ++i) points_.erase(std::get<3>(order[i]));
    dirty_ = true;
  }
  // Observations of removed points go; key frames observing nothing any more go too (except
  // the newest, the reference of the key-frame decision).
  for (KeyFrame& k : keyFrames_) {
    for (auto it = k.observations.begin(); it != k.observations.end();) {
      it = points_.count(it->first) ? std::next(it) : k.observations.erase(it);
    }
  }
  while (keyFrames_.size() > 1 && keyFrames_.front().observations.empty()) keyFrames_.pop_front();
}

BundleAdjustmentSummary VisualLocalMap::adjust(int maxFrames, const BundleAdjustmentOptions& options) {
  BundleAdjustmentSummary summary;
  const size_t n = maxFrames > 0 ? std::min(keyFrames_.size(), static_cast<size_t>(maxFrames)) : keyFrames_.size();
  if (n < 2) {
    summary.message = "fewer than 2 key frames";
    return summary;
  }
  const size_t first = keyFrames_.size() - n;
  std::map<int, BundleAdjustmentFrame> frames;
  std::map<int, cv::Point3f> positions;
  std::vector<BundleAdjustmentObservation> observations;
  std::vector<std::pair<size_t, int>> origin;  // (key frame index, point id) of each observation
  for (size_t k = first; k < keyFrames_.size(); ++k) {
    const KeyFrame& kf = keyFrames_[k];
    frames[static_cast<int>(k)] = {kf.pose, kf.model, k == first, kf.baseline};
    for (const auto& [id, o] : kf.observations) {
      auto p = points_.find(id);
      if (p == points_.end()) continue;
      positions[id] = p->second.position;
      observations.push_back({static_cast<int>(k), id, o.uv, o.depth});
      origin.emplace_back(k, id);
    }
  }
  summary = bundleAdjust(frames, positions, observations, options);
  if (!summary.success) return summary;
  for (size_t k = first; k < keyFrames_.size(); ++k) keyFrames_[k].pose = frames[static_cast<int>(k)].pose;
  for (const auto& [id, position] : positions) points_[id].position = position;
  for (size_t i : summary.outliers) keyFrames_[origin[i].first].observations.erase(origin[i].second);
  dirty_ = true;
  return summary;
}

}  // namespace rtabmap::odometry_detail

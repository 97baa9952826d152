#include "IcpScanIndex.h"

#include <flann/flann.hpp>

#include <algorithm>
#include <cmath>

namespace rtabmap::icp {

struct ScanIndex::KdTree {
  std::vector<float> data;  // x y z per point, owned here: FLANN keeps a pointer to it
  std::unique_ptr<flann::KDTreeSingleIndex<flann::L2_Simple<float>>> index;
};

std::int64_t ScanIndex::cellOf(float v) const { return static_cast<std::int64_t>(std::floor(v * inverse_)); }

std::uint64_t ScanIndex::cellKey(const Eigen::Vector3f& p, int dx, int dy) const {
  // 32 bits per axis: no two cells of any map share a key.
  const auto pack = [](std::int64_t i) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)); };
  return (pack(cellOf(p.x()) + dx) << 32) | pack(cellOf(p.y()) + dy);
}

float ScanIndex::distance2(const Eigen::Vector3f& a, const Eigen::Vector3f& b) const {
  const float dx = a.x() - b.x(), dy = a.y() - b.y(), dz = is2d_ ? 0.0f : a.z() - b.z();
  return dx * dx + dy * dy + dz * dz;
}

template <typename F>
void ScanIndex::visitNeighbours(const Eigen::Vector3f& q, F&& visit) const {
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const auto it = cells_.find(cellKey(q, dx, dy));
      if (it == cells_.end()) continue;
      for (const long id : it->second) {
        const int position = static_cast<int>(id - firstId_);
        visit(position, distance2(positions_[static_cast<size_t>(position)], q));
      }
    }
  }
}

void ScanIndex::clear() {
  positions_.clear();
  cells_.clear();
  tree_.reset();
  firstId_ = 0;
}

void ScanIndex::build(const pcl::PointCloud<pcl::PointNormal>& cloud, float maxDistance, bool is2d) {
  clear();
  maxDistance_ = maxDistance;
  inverse_ = 1.0f / maxDistance;
  is2d_ = is2d;
  append(cloud);
}

void ScanIndex::append(const pcl::PointCloud<pcl::PointNormal>& points) {
  positions_.reserve(positions_.size() + points.size());
  for (const auto& p : points) {
    const Eigen::Vector3f position(p.x, p.y, is2d_ ? 0.0f : p.z);
    if (is2d_) cells_[cellKey(position)].push_back(firstId_ + static_cast<long>(positions_.size()));
    positions_.push_back(position);
  }
  if (!is2d_) rebuildTree();
}

void ScanIndex::removeOldest(int count) {
  count = std::min(count, size());
  if (count <= 0) return;
  if (is2d_) {
    // The globally oldest points are the oldest of their cells: each is its cell's first id.
    for (int i = 0; i < count; ++i) {
      const auto it = cells_.find(cellKey(positions_[static_cast<size_t>(i)]));
      if (it == cells_.end()) continue;
      it->second.erase(it->second.begin());
      if (it->second.empty()) cells_.erase(it);
    }
  }
  positions_.erase(positions_.begin(), positions_.begin() + count);
  firstId_ += count;
  if (!is2d_) rebuildTree();
}

void ScanIndex::rebuildTree() {
  tree_.reset();
  if (positions_.empty()) return;
  auto tree = std::make_shared<KdTree>();
  tree->data.reserve(positions_.size() * 3);
  for (const auto& p : positions_) tree->data.insert(tree->data.end(), {p.x(), p.y(), p.z()});
  const flann::Matrix<float> matrix(tree->data.data(), positions_.size(), 3);
  tree->index = std::make_unique<flann::KDTreeSingleIndex<flann::L2_Simple<float>>>(
      matrix, flann::KDTreeSingleIndexParams(15));
  tree->index->buildIndex();
  tree_ = tree;
}

int ScanIndex::nearest(const Eigen::Vector3f& query, float maxDistance2, float* distanceOut) const {
  if (positions_.empty()) return -1;
  if (!is2d_) {
    float q[3] = {query.x(), query.y(), query.z()};
    int index = -1;
    float d2 = 0.0f;
    flann::Matrix<int> indices(&index, 1, 1);
    flann::Matrix<float> distances(&d2, 1, 1);
    flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED, 0.0f, false);
    tree_->index->knnSearch(flann::Matrix<float>(q, 1, 3), indices, distances, 1, params);
    if (index < 0 || d2 > maxDistance2) return -1;
    if (distanceOut) *distanceOut = d2;
    return index;
  }
  int best = -1;
  float bestDistance = maxDistance2;
  visitNeighbours(query, [&](int position, float d2) {
    if (d2 <= bestDistance) {
      bestDistance = d2;
      best = position;
    }
  });
  if (best >= 0 && distanceOut) *distanceOut = bestDistance;
  return best;
}

void ScanIndex::within(const Eigen::Vector3f& query, float radius, std::vector<std::pair<int, float>>* out) const {
  out->clear();
  if (positions_.empty()) return;
  const float r2 = radius * radius;
  if (!is2d_) {
    float q[3] = {query.x(), query.y(), query.z()};
    std::vector<std::vector<int>> indices;
    std::vector<std::vector<float>> distances;
    flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED, 0.0f, false);
    tree_->index->radiusSearch(flann::Matrix<float>(q, 1, 3), indices, distances, r2, params);
    for (size_t i = 0; i < indices[0].size(); ++i) out->emplace_back(indices[0][i], distances[0][i]);
    return;
  }
  visitNeighbours(query, [&](int position, float d2) {
    if (d2 <= r2) out->emplace_back(position, d2);
  });
}

}  // namespace rtabmap::icp

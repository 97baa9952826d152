#pragma once
// Private: the nearest-neighbour search of ICP over a target cloud, within a maximum distance.
//
// Why not PCL's kd-tree: ICP asks one nearest neighbour per scan point per iteration, and
// pcl::search::KdTree costs ~2.6 us per query on these machines (FLANN ~0.8 us, the rest PCL's
// per-query wrapping). For a 180-beam scan over 10-20 iterations that alone is 5-9 ms, several
// times the 2D odometry's budget. So:
//   2D: a hashed uniform grid with cells as large as the maximum distance: the nearest point
//       within it lies in the 3x3 cells around the query, a handful of points on a scan line
//       (~0.1-0.2 us per query).
//   3D: FLANN's single kd-tree, called directly. A grid with cells of a 3D ICP's correspondence
//       distance (0.5-1 m) holds hundreds of surface points per 3x3x3 block.
#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace rtabmap::icp {

class ScanIndex {
 public:
  // Indexes the points of `cloud` (copied: the index stays valid if the cloud changes) for
  // queries up to `maxDistance` (> 0); is2d ignores z and uses the grid.
  void build(const pcl::PointCloud<pcl::PointNormal>& cloud, float maxDistance, bool is2d);
  // Adds points after the current ones, and drops the `count` oldest (first) ones: what a
  // scan map does at each key frame. The grid does both in place, in time proportional to the
  // points touched, so a key frame costs no more than a scan; the 3D tree is rebuilt.
  void append(const pcl::PointCloud<pcl::PointNormal>& points);
  void removeOldest(int count);
  void clear();
  bool empty() const { return positions_.empty(); }
  int size() const { return static_cast<int>(positions_.size()); }
  // The largest query distance the index answers exactly.
  float maxDistance() const { return maxDistance_; }

  // Results are positions in the indexed order: 0 is the oldest point still indexed (the
  // first of `cloud` after build, if nothing was removed).
  //
  // The nearest point at squared distance at most maxDistance2 (whose root must not exceed
  // maxDistance()), or -1.
  int nearest(const Eigen::Vector3f& query, float maxDistance2, float* distance2 = nullptr) const;
  // Every point within `radius` (<= maxDistance()) of query: (position, squared distance), in
  // no particular order. `out` is cleared first.
  void within(const Eigen::Vector3f& query, float radius, std::vector<std::pair<int, float>>* out) const;

 private:
  struct KdTree;  // FLANN, kept out of this header

  std::int64_t cellOf(float v) const;
  std::uint64_t cellKey(const Eigen::Vector3f& p, int dx = 0, int dy = 0) const;
  float distance2(const Eigen::Vector3f& a, const Eigen::Vector3f& b) const;
  void rebuildTree();
  template <typename F>
  void visitNeighbours(const Eigen::Vector3f& q, F&& visit) const;

  float maxDistance_ = 0.0f;
  float inverse_ = 0.0f;
  bool is2d_ = true;
  std::vector<Eigen::Vector3f> positions_;  // oldest first
  long firstId_ = 0;                        // id of positions_[0]; a point's id never changes
  // 2D: the ids of each cell's points, ascending (oldest first).
  std::unordered_map<std::uint64_t, std::vector<long>> cells_;
  std::shared_ptr<const KdTree> tree_;  // 3D; immutable once built, so copies may share it
};

}  // namespace rtabmap::icp

#pragma once
// Free space of one local grid through OctoMap's ray casting (OcTreeBaseImpl::computeRayKeys,
// a 3D DDA over the tree's keys): the voxels crossed by rays from a view point to end points,
// each voxel once, never an end voxel. Used by the local grid's 3D ray tracing and by the
// global OctoMap when a node carries no empty voxels. Internal to the maps area.
//
// Each voxel must come out once per grid (OctoMap's insertPointCloud does the same with a hash
// set). Rays from one view point overlap heavily near it, and a hash set insert per ray step
// costs more than the step: when the rays' bounding box is small enough, a dense box of stamps
// (one uint32 per voxel, reused between calls) replaces the hash set.
#include <octomap/OcTreeKey.h>
#include <octomap/octomap_types.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rtabmap::maps_detail {

class RayCaster {
 public:
  // Boxes up to this many voxels use stamps (64 M voxels = 256 MB at most; a 7-Scenes or
  // Kinect frame needs well under 1 M).
  static constexpr size_t kMaxBoxVoxels = size_t(64) << 20;

  // Appends to `free` the keys crossed by the rays origin -> ends[i] (excluding the end voxels and
  // every voxel listed in `occupied`). Rays longer than maxRange (> 0) are truncated, and then
  // include their last voxel (nothing was hit there). Returns the number of rays cast.
  template <class Tree>
  size_t cast(const Tree& tree, const octomap::point3d& origin, const std::vector<octomap::point3d>& ends,
              const std::vector<octomap::OcTreeKey>& occupied, float maxRange,
              std::vector<octomap::OcTreeKey>& free) {
    octomap::OcTreeKey originKey;
    if (!tree.coordToKeyChecked(origin, originKey)) return 0;
    // Bounding box of the rays in keys.
    octomap::OcTreeKey lo = originKey, hi = originKey;
    std::vector<octomap::point3d> targets;
    std::vector<bool> truncated;
    targets.reserve(ends.size());
    truncated.reserve(ends.size());
    for (const octomap::point3d& e : ends) {
      octomap::point3d end = e;
      bool cut = false;
      if (maxRange > 0.0f) {
        const octomap::point3d d = e - origin;
        const double len = d.norm();
        if (len > maxRange) {
          end = origin + d * static_cast<float>(maxRange / len);
          cut = true;
        }
      }
      octomap::OcTreeKey k;
      if (!tree.coordToKeyChecked(end, k)) continue;
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], k[a]);
        hi[a] = std::max(hi[a], k[a]);
      }
      targets.push_back(end);
      truncated.push_back(cut);
    }
    const size_t nx = size_t(hi[0] - lo[0]) + 1, ny = size_t(hi[1] - lo[1]) + 1,
                 nz = size_t(hi[2] - lo[2]) + 1;
    const bool dense = nx * ny * nz <= kMaxBoxVoxels;
    if (dense) beginBox(lo, nx, ny, nz);
    else hashed_.clear();
    for (const octomap::OcTreeKey& k : occupied) {
      if (dense) { if (inBox(k)) stamps_[boxIndex(k)] = stamp_; }
      else hashed_.insert(k);
    }
    auto visit = [&](const octomap::OcTreeKey& k) {
      if (dense) {
        uint32_t& s = stamps_[boxIndex(k)];
        if (s == stamp_) return;
        s = stamp_;
      } else if (!hashed_.insert(k).second) {
        return;
      }
      free.push_back(k);
    };
    for (size_t i = 0; i < targets.size(); ++i) {
      if (!tree.computeRayKeys(origin, targets[i], ray_)) continue;
      for (const octomap::OcTreeKey& k : ray_) visit(k);
      if (truncated[i]) {
        octomap::OcTreeKey last;
        if (tree.coordToKeyChecked(targets[i], last)) visit(last);
      }
    }
    return targets.size();
  }

 private:
  void beginBox(const octomap::OcTreeKey& lo, size_t nx, size_t ny, size_t nz) {
    lo_ = lo;
    nx_ = nx; ny_ = ny; nz_ = nz;
    const size_t n = nx * ny * nz;
    if (stamps_.size() < n) {
      stamps_.assign(n, 0u);
      stamp_ = 0;
    }
    if (++stamp_ == 0) {  // wrapped: forget every old stamp
      std::fill(stamps_.begin(), stamps_.end(), 0u);
      stamp_ = 1;
    }
  }
  bool inBox(const octomap::OcTreeKey& k) const {
    return k[0] >= lo_[0] && k[1] >= lo_[1] && k[2] >= lo_[2] && size_t(k[0] - lo_[0]) < nx_ &&
           size_t(k[1] - lo_[1]) < ny_ && size_t(k[2] - lo_[2]) < nz_;
  }
  size_t boxIndex(const octomap::OcTreeKey& k) const {
    return (size_t(k[0] - lo_[0]) * ny_ + size_t(k[1] - lo_[1])) * nz_ + size_t(k[2] - lo_[2]);
  }

  octomap::KeyRay ray_;
  std::vector<uint32_t> stamps_;
  uint32_t stamp_ = 0;
  octomap::OcTreeKey lo_;
  size_t nx_ = 0, ny_ = 0, nz_ = 0;
  octomap::KeySet hashed_;
};

}  // namespace rtabmap::maps_detail

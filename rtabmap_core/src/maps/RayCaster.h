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
//
// Many rays are cast on two threads (computeRayKeys only reads the tree): the second half of the
// rays on a worker with its own visited set, then its voxels not already seen by the first half
// are appended in its order. That is exactly the serial output, same keys in the same order.
#include <octomap/OcTreeKey.h>
#include <octomap/octomap_types.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>

namespace rtabmap::maps_detail {

// Voxels already seen during one cast: dense stamps over the rays' bounding box, or a hash set
// when the box is too large.
class VisitedVoxels {
 public:
  // Boxes up to this many voxels use stamps (64 M voxels = 256 MB at most; a 7-Scenes or
  // Kinect frame needs well under 1 M).
  static constexpr size_t kMaxBoxVoxels = size_t(64) << 20;

  void begin(const octomap::OcTreeKey& lo, const octomap::OcTreeKey& hi) {
    lo_ = lo;
    nx_ = size_t(hi[0] - lo[0]) + 1;
    ny_ = size_t(hi[1] - lo[1]) + 1;
    nz_ = size_t(hi[2] - lo[2]) + 1;
    const size_t n = nx_ * ny_ * nz_;
    dense_ = n <= kMaxBoxVoxels;
    if (!dense_) {
      hashed_.clear();
      return;
    }
    if (stamps_.size() < n) {
      stamps_.assign(n, 0u);
      stamp_ = 0;
    }
    if (++stamp_ == 0) {  // wrapped: forget every old stamp
      std::fill(stamps_.begin(), stamps_.end(), 0u);
      stamp_ = 1;
    }
  }
  // Marks k (which may lie outside the box: it then can never be visited). True if it was new.
  bool insert(const octomap::OcTreeKey& k) {
    if (!dense_) return hashed_.insert(k).second;
    if (!inBox(k)) return true;
    uint32_t& s = stamps_[index(k)];
    if (s == stamp_) return false;
    s = stamp_;
    return true;
  }

 private:
  bool inBox(const octomap::OcTreeKey& k) const {
    return k[0] >= lo_[0] && k[1] >= lo_[1] && k[2] >= lo_[2] && size_t(k[0] - lo_[0]) < nx_ &&
           size_t(k[1] - lo_[1]) < ny_ && size_t(k[2] - lo_[2]) < nz_;
  }
  size_t index(const octomap::OcTreeKey& k) const {
    return (size_t(k[0] - lo_[0]) * ny_ + size_t(k[1] - lo_[1])) * nz_ + size_t(k[2] - lo_[2]);
  }

  bool dense_ = true;
  std::vector<uint32_t> stamps_;
  uint32_t stamp_ = 0;
  octomap::OcTreeKey lo_;
  size_t nx_ = 0, ny_ = 0, nz_ = 0;
  octomap::KeySet hashed_;
};

class RayCaster {
 public:
  // Below this many rays one thread does it all (starting a thread costs tens of microseconds).
  static constexpr size_t kMinRaysPerThread = 512;

  // Appends to `free` the keys crossed by the rays origin -> ends[i] (excluding the end voxels and
  // every voxel listed in `occupied`). Rays longer than maxRange (> 0) are truncated, and then
  // include their last voxel (nothing was hit there). Returns the number of rays cast.
  template <class Tree>
  size_t cast(const Tree& tree, const octomap::point3d& origin, const std::vector<octomap::point3d>& ends,
              const std::vector<octomap::OcTreeKey>& occupied, float maxRange,
              std::vector<octomap::OcTreeKey>& free) {
    octomap::OcTreeKey lo, hi;
    if (!tree.coordToKeyChecked(origin, lo)) return 0;
    hi = lo;
    prepareTargets(tree, origin, ends, maxRange, lo, hi);
    const size_t n = targets_.size();
    static const bool twoCores = std::thread::hardware_concurrency() > 1;
    const size_t split = n >= 2 * kMinRaysPerThread && twoCores ? n / 2 : n;
    main_.begin(lo, hi);
    for (const octomap::OcTreeKey& k : occupied) main_.insert(k);
    if (split < n) {
      // The second half on a worker; it excludes the occupied voxels too, and the first half's
      // voxels are removed from its output when merging.
      std::thread worker;
      std::exception_ptr workerFailure;
      try {
        worker = std::thread([&] {
          try {
            worker_.visited.begin(lo, hi);
            for (const octomap::OcTreeKey& k : occupied) worker_.visited.insert(k);
            worker_.free.clear();
            castRange(tree, origin, split, n, worker_, worker_.free);
          } catch (...) {
            workerFailure = std::current_exception();
          }
        });
      } catch (const std::system_error&) {  // no thread available: all on this one
        castRange(tree, origin, 0, n, mainState(), free);
        return n;
      }
      try {
        castRange(tree, origin, 0, split, mainState(), free);
      } catch (...) {
        worker.join();
        throw;
      }
      worker.join();
      if (workerFailure) std::rethrow_exception(workerFailure);
      for (const octomap::OcTreeKey& k : worker_.free) {
        if (main_.insert(k)) free.push_back(k);
      }
      return n;
    }
    castRange(tree, origin, 0, n, mainState(), free);
    return n;
  }

 private:
  struct ThreadState {
    VisitedVoxels visited;
    octomap::KeyRay ray;
    std::vector<octomap::OcTreeKey> free;
  };
  // The main thread's state lives in separate members so that its visited set outlives a cast
  // for the merge.
  struct MainRef {
    VisitedVoxels& visited;
    octomap::KeyRay& ray;
  };
  MainRef mainState() { return {main_, mainRay_}; }

  // The rays' end points (cut at maxRange) and their bounding box with the origin, in keys.
  template <class Tree>
  void prepareTargets(const Tree& tree, const octomap::point3d& origin, const std::vector<octomap::point3d>& ends,
                      float maxRange, octomap::OcTreeKey& lo, octomap::OcTreeKey& hi) {
    targets_.clear();
    truncated_.clear();
    targets_.reserve(ends.size());
    truncated_.reserve(ends.size());
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
      targets_.push_back(end);
      truncated_.push_back(cut);
    }
  }

  // Rays [first, last) of targets_, new voxels appended to out.
  template <class Tree, class State>
  void castRange(const Tree& tree, const octomap::point3d& origin, size_t first, size_t last, State&& st,
                 std::vector<octomap::OcTreeKey>& out) const {
    for (size_t i = first; i < last; ++i) {
      if (!tree.computeRayKeys(origin, targets_[i], st.ray)) continue;
      for (const octomap::OcTreeKey& k : st.ray) {
        if (st.visited.insert(k)) out.push_back(k);
      }
      if (truncated_[i]) {
        octomap::OcTreeKey k;
        if (tree.coordToKeyChecked(targets_[i], k) && st.visited.insert(k)) out.push_back(k);
      }
    }
  }

  std::vector<octomap::point3d> targets_;
  std::vector<bool> truncated_;
  VisitedVoxels main_;
  octomap::KeyRay mainRay_;
  ThreadState worker_;
};

}  // namespace rtabmap::maps_detail

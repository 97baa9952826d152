#pragma once
// Free space of one local grid through OctoMap's ray casting (OcTreeBaseImpl::computeRayKeys,
// a 3D DDA over the tree's keys): the voxels crossed by rays from a view point to end points,
// each voxel once, never an end voxel. Used by the local grid's 3D ray tracing and by the
// global OctoMap when a node carries no empty voxels. Internal to the maps area.
//
// Each voxel must come out once per grid (OctoMap's insertPointCloud does the same with a hash
// set). Rays from one view point overlap heavily near it, and a hash set insert per ray step
// costs more than the step: when the rays' bounding box is small enough, each ray step sets a
// bit of a VoxelBitset instead, and the set is read back once, in Morton code order (the order
// the octree update needs). Larger boxes (and the rare step just outside the box) go through a
// hash set, sorted afterwards.
//
// Many rays are cast on two threads (computeRayKeys only reads the tree): the second half of the
// rays on a worker with its own bitset; the union of both is the serial result.
#include <octomap/OcTreeKey.h>
#include <octomap/octomap_types.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>

#include "VoxelBitset.h"

namespace rtabmap::maps_detail {

class RayCaster {
 public:
  // Below this many rays one thread does it all (starting a thread costs tens of microseconds).
  static constexpr size_t kMinRaysPerThread = 512;

  // Appends to `free` the keys crossed by the rays origin -> ends[i] (excluding the end voxels and
  // every voxel listed in `occupied`), each once, in increasing Morton code. Rays longer than
  // maxRange (> 0) are truncated, and then include their last voxel (nothing was hit there).
  // Returns the number of rays cast.
  template <class Tree>
  size_t cast(const Tree& tree, const octomap::point3d& origin, const std::vector<octomap::point3d>& ends,
              const std::vector<octomap::OcTreeKey>& occupied, float maxRange,
              std::vector<octomap::OcTreeKey>& free) {
    octomap::OcTreeKey lo, hi;
    if (!tree.coordToKeyChecked(origin, lo)) return 0;
    hi = lo;
    prepareTargets(tree, origin, ends, maxRange, lo, hi);
    const size_t n = targets_.size();
    const bool dense = main_.bits.reset(lo, hi);
    main_.outside.clear();
    static const bool twoCores = std::thread::hardware_concurrency() > 1;
    const size_t split = n >= 2 * kMinRaysPerThread && twoCores ? n / 2 : n;
    bool merged = false;
    if (split < n && dense) {
      std::thread worker;
      std::exception_ptr workerFailure;
      try {
        worker = std::thread([&] {
          try {
            worker_.bits.reset(lo, hi);
            worker_.outside.clear();
            castRange(tree, origin, split, n, true, worker_);
          } catch (...) {
            workerFailure = std::current_exception();
          }
        });
      } catch (const std::system_error&) {  // no thread available: all on this one
        worker = std::thread();
      }
      if (worker.joinable()) {
        try {
          castRange(tree, origin, 0, split, true, main_);
        } catch (...) {
          worker.join();
          throw;
        }
        worker.join();
        if (workerFailure) std::rethrow_exception(workerFailure);
        merged = true;
      }
    }
    if (!merged) castRange(tree, origin, 0, n, dense, main_);
    collect(dense, merged, occupied, free);
    return n;
  }

 private:
  struct ThreadState {
    VoxelBitset bits;
    std::vector<octomap::OcTreeKey> outside;  // keys outside the bitset's box, in ray order
    octomap::KeyRay ray;
  };

  // Free keys: the bitsets' voxels without the occupied ones, then the voxels outside the box
  // (deduplicated and sorted) merged in.
  void collect(bool dense, bool merged, const std::vector<octomap::OcTreeKey>& occupied,
               std::vector<octomap::OcTreeKey>& free) {
    const size_t first = free.size();
    octomap::KeySet occupiedOutside;
    if (dense) {
      occupiedBits_.reset(boxLo_, boxHi_);
      for (const octomap::OcTreeKey& k : occupied) {
        if (occupiedBits_.contains(k)) occupiedBits_.set(k);
        else occupiedOutside.insert(k);
      }
      VoxelBitset::collect(main_.bits, merged ? &worker_.bits : nullptr, &occupiedBits_, free);
    } else {
      occupiedOutside.insert(occupied.begin(), occupied.end());
    }
    const size_t inBox = free.size();
    octomap::KeySet seen;
    for (const std::vector<octomap::OcTreeKey>* list : {&main_.outside, &worker_.outside}) {
      if (list == &worker_.outside && !merged) break;
      for (const octomap::OcTreeKey& k : *list) {
        if (!occupiedOutside.count(k) && seen.insert(k).second) free.push_back(k);
      }
    }
    if (free.size() == inBox) return;
    auto byMorton = [](const octomap::OcTreeKey& a, const octomap::OcTreeKey& b) { return mortonCode(a) < mortonCode(b); };
    std::sort(free.begin() + static_cast<std::ptrdiff_t>(inBox), free.end(), byMorton);
    std::inplace_merge(free.begin() + static_cast<std::ptrdiff_t>(first), free.begin() + static_cast<std::ptrdiff_t>(inBox),
                       free.end(), byMorton);
  }

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
    boxLo_ = lo;
    boxHi_ = hi;
  }

  // Rays [first, last) of targets_, their voxels marked in st.bits (when `dense`) or listed in
  // st.outside.
  template <class Tree>
  void castRange(const Tree& tree, const octomap::point3d& origin, size_t first, size_t last, bool dense,
                 ThreadState& st) const {
    auto mark = [&](const octomap::OcTreeKey& k) {
      if (dense && st.bits.contains(k)) st.bits.set(k);
      else st.outside.push_back(k);
    };
    for (size_t i = first; i < last; ++i) {
      if (!tree.computeRayKeys(origin, targets_[i], st.ray)) continue;
      for (const octomap::OcTreeKey& k : st.ray) mark(k);
      if (truncated_[i]) {
        octomap::OcTreeKey k;
        if (tree.coordToKeyChecked(targets_[i], k)) mark(k);
      }
    }
  }

  std::vector<octomap::point3d> targets_;
  std::vector<bool> truncated_;
  octomap::OcTreeKey boxLo_, boxHi_;
  ThreadState main_, worker_;
  VoxelBitset occupiedBits_;
};

}  // namespace rtabmap::maps_detail

#pragma once
// Free space of one local grid by OctoMap's ray casting: the voxels crossed by rays from a view
// point to end points, each voxel once, never an end voxel. Used by the local grid's 3D ray
// tracing and by the global OctoMap when a node carries no empty voxels. Internal to the maps
// area.
//
// The walk is the 3D DDA of Amanatides & Woo with the arithmetic of OctoMap's
// OcTreeBaseImpl::computeRayKeys (same float direction, same double tMax, same ties, same early
// stop when rounding misses the end voxel), so the voxels are the same as liboctomap's, and the
// tests compare them with it. It is written here rather than called because the call fills a
// KeyRay that is then read back, its tMax live in an array indexed by the axis, and its axis
// choice is a branch the CPU mispredicts about every other step: fused with the marking, in
// registers and branch-free, a step costs about half as much, and the rays were close to half
// of an OctoMap update. (Keys are ints here, where computeRayKeys wraps them at 16 bits: the
// two could differ only for a step past the edge of the tree's key range, 65,536 voxels a side,
// and both then store the same wrapped key.)
//
// Each voxel must come out once per grid (OctoMap's insertPointCloud does the same with a hash
// set). Rays from one view point overlap heavily near it, and a hash set insert per ray step
// costs more than the step: when the rays' bounding box is small enough, each ray step sets a
// bit of a VoxelBitset instead, and the set is read back once, in Morton code order (the order
// the octree update needs). Larger boxes (and the rare step just outside the box) go through a
// hash set, sorted afterwards.
//
// Many rays are cast on two threads (the walk only reads the tree's resolution and key
// lattice): the second half of the rays on a worker with its own bitset; the union of both is
// the serial result.
#include <octomap/OcTreeKey.h>
#include <octomap/octomap_types.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
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
    originKey_ = lo;
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
    targetKeys_.clear();
    truncated_.clear();
    targets_.reserve(ends.size());
    targetKeys_.reserve(ends.size());
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
      targetKeys_.push_back(k);
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
    auto mark = [&](int k0, int k1, int k2) {
      if (dense && st.bits.trySet(unsigned(k0), unsigned(k1), unsigned(k2))) return;
      st.outside.emplace_back(static_cast<octomap::key_type>(k0), static_cast<octomap::key_type>(k1),
                              static_cast<octomap::key_type>(k2));
    };
    for (size_t i = first; i < last; ++i) {
      walk(tree, origin, targets_[i], targetKeys_[i], mark);
      if (truncated_[i]) mark(targetKeys_[i][0], targetKeys_[i][1], targetKeys_[i][2]);
    }
  }

  // Calls mark(k0, k1, k2) for each voxel the ray origin -> end crosses, from the origin's
  // voxel, without the end's voxel (`to`); nothing when both are in one voxel. See the file
  // comment.
  template <class Tree, class Mark>
  void walk(const Tree& tree, const octomap::point3d& origin, const octomap::point3d& end, const octomap::OcTreeKey& to,
            Mark&& mark) const {
    if (originKey_ == to) return;
    mark(originKey_[0], originKey_[1], originKey_[2]);
    octomap::point3d direction = end - origin;
    const float length = static_cast<float>(direction.norm());
    direction /= length;
    const double res = tree.getResolution();
    int step[3];
    double tMax[3], tDelta[3];
    for (int a = 0; a < 3; ++a) {
      step[a] = direction(a) > 0.0f ? 1 : (direction(a) < 0.0f ? -1 : 0);
      if (step[a] != 0) {
        double border = tree.keyToCoord(originKey_[a]);
        border += static_cast<float>(step[a] * res * 0.5);
        tMax[a] = (border - origin(a)) / direction(a);
        tDelta[a] = res / std::fabs(direction(a));
      } else {
        tMax[a] = tDelta[a] = std::numeric_limits<double>::max();
      }
    }
    // Scalars, not arrays: the loop is one dependency chain through the tMax values, and an
    // indexed store then load of them costs more than the arithmetic.
    double t0 = tMax[0], t1 = tMax[1], t2 = tMax[2];
    const double d0 = tDelta[0], d1 = tDelta[1], d2 = tDelta[2];
    const double len = length;
    int k0 = originKey_[0], k1 = originKey_[1], k2 = originKey_[2];
    const int e0 = to[0], e1 = to[1], e2 = to[2];
    for (;;) {
      // The axis of the nearest voxel border, ties broken as computeRayKeys does; every axis is
      // updated, by its step or by 0, rather than branched on (the comparisons come out at
      // random along a ray). Adding 0.0 leaves a tMax unchanged.
      const bool c01 = t0 < t1, c02 = t0 < t2, c12 = t1 < t2;
      const bool x = c01 && c02, y = !c01 && c12, z = !x && !y;
      const uint64_t mx = 0 - uint64_t(x), my = 0 - uint64_t(y), mz = 0 - uint64_t(z);
      k0 += step[0] & -int(x);
      k1 += step[1] & -int(y);
      k2 += step[2] & -int(z);
      t0 += masked(d0, mx);
      t1 += masked(d1, my);
      t2 += masked(d2, mz);
      if (k0 == e0 && k1 == e1 && k2 == e2) return;
      // Rounding can step past the end voxel's neighbours without entering it: stop at the length.
      const double t01 = t1 < t0 ? t1 : t0;  // std::min's result by value: the tMax stay in registers
      if ((t2 < t01 ? t2 : t01) > len) return;
      mark(k0, k1, k2);
    }
  }

  // v where the mask is all ones, +0.0 where it is zero: a select the compiler cannot turn into
  // a branch (with ?: it did, and mispredicted about every other step).
  static double masked(double v, uint64_t mask) {
    uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    b &= mask;
    std::memcpy(&v, &b, sizeof v);
    return v;
  }

  std::vector<octomap::point3d> targets_;
  std::vector<octomap::OcTreeKey> targetKeys_;
  std::vector<bool> truncated_;
  octomap::OcTreeKey originKey_;
  octomap::OcTreeKey boxLo_, boxHi_;
  ThreadState main_, worker_;
  VoxelBitset occupiedBits_;
};

}  // namespace rtabmap::maps_detail

#pragma once
// One node's voxel updates applied to an OcTree in one descent. OcTree::updateNode walks the 16
// levels from the root for every voxel; a node's voxels are neighbours, so sorted in the tree's
// child order (the Morton code of their keys) they share most of that walk. The descent also
// refreshes the inner nodes it passed (maximum of the children, as updateInnerOccupancy does,
// and their mean colour), so no whole-tree pass is needed after it. Same values as updateNode
// with lazy evaluation followed by updateInnerOccupancy: new voxels start at log-odds 0, each
// update adds its log-odds and clamps. Internal to the maps area.
//
// The sort is a stable radix sort on (Morton code, kind): tens of thousands of updates per node
// sort several times faster than with comparisons, and stability makes the result deterministic
// (of several points of one kind in a voxel, the first one gives the colour).
#include <octomap/ColorOcTree.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "VoxelBitset.h"

namespace rtabmap::maps_detail {

struct VoxelUpdate {
  enum Kind : uint8_t { kObstacle = 0, kGround = 1, kFree = 2 };  // priority order
  uint64_t morton = 0;
  octomap::OcTreeKey key;
  Kind kind = kFree;
  bool hasColor = false;  // occupied voxels of a coloured grid
  uint8_t r = 0, g = 0, b = 0;
};

class OctreeBatch {
 public:
  // Applies one node's updates: hit for obstacle and ground voxels, miss for free ones, each
  // voxel once, the strongest kind winning (obstacle, then ground, then free: a voxel this node
  // saw occupied is not freed by its own rays), the first update of that kind in `updates`
  // giving the colour. `sortedFree`: more free voxels, already in increasing Morton code and
  // without duplicates (a VoxelBitset's keys: the 20,000 free voxels of a frame need no sort).
  // Leaves `updates` sorted, merged with `sortedFree` and without duplicates. The buffers are
  // kept between calls.
  void apply(octomap::ColorOcTree& tree, std::vector<VoxelUpdate>& updates,
             const std::vector<octomap::OcTreeKey>& sortedFree, float hit, float miss);

 private:
  struct SortItem {
    uint64_t code;  // Morton code << 2 | kind
    uint32_t index;
  };
  void sortByVoxel(std::vector<VoxelUpdate>& updates);
  void mergeFree(std::vector<VoxelUpdate>& updates, const std::vector<octomap::OcTreeKey>& sortedFree);
  void descend(octomap::ColorOcTreeNode* node, unsigned depth, bool created, VoxelUpdate* begin, VoxelUpdate* end);
  static VoxelUpdate* runEnd(VoxelUpdate* b, VoxelUpdate* end, unsigned shift, uint64_t prefix);
  void updateFromChildren(const octomap::ColorOcTree& tree, octomap::ColorOcTreeNode* node) const;

  octomap::ColorOcTree* tree_ = nullptr;
  bool colors_ = false;
  float hit_ = 0.0f, miss_ = 0.0f, clampMin_ = 0.0f, clampMax_ = 0.0f;
  std::vector<SortItem> items_, scratch_;
  std::vector<uint32_t> counts_;
  std::vector<VoxelUpdate> sorted_;
};

inline void OctreeBatch::apply(octomap::ColorOcTree& tree, std::vector<VoxelUpdate>& updates,
                               const std::vector<octomap::OcTreeKey>& sortedFree, float hit, float miss) {
  if (updates.empty() && sortedFree.empty()) return;
  tree_ = &tree;
  hit_ = hit;
  miss_ = miss;
  clampMin_ = tree.getClampingThresMinLog();
  clampMax_ = tree.getClampingThresMaxLog();
  if (!updates.empty()) sortByVoxel(updates);
  mergeFree(updates, sortedFree);
  colors_ = false;
  for (const VoxelUpdate& u : updates) colors_ = colors_ || u.hasColor;
  if (!tree.getRoot()) {
    // The root is private to the tree: let it create the root (and a path, at log-odds 0, the
    // value any new voxel starts from) with a null update.
    tree.updateNode(updates.front().key, 0.0f, true);
  }
  descend(tree.getRoot(), 0, false, updates.data(), updates.data() + updates.size());
}

// LSD radix sort (11-bit digits, stable) over the bits where the codes differ: a node's voxels
// share their high Morton bits, so two or three passes usually do. Then one update per voxel,
// the first of the sorted run (strongest kind, first in input order).
inline void OctreeBatch::sortByVoxel(std::vector<VoxelUpdate>& updates) {
  const size_t n = updates.size();
  items_.resize(n);
  scratch_.resize(n);
  uint64_t differing = 0;
  for (size_t i = 0; i < n; ++i) {
    VoxelUpdate& u = updates[i];
    u.morton = mortonCode(u.key);
    items_[i] = {(u.morton << 2) | u.kind, static_cast<uint32_t>(i)};
    differing |= items_[i].code ^ items_[0].code;
  }
  constexpr unsigned kDigitBits = 11;
  constexpr size_t kBuckets = size_t(1) << kDigitBits;
  std::vector<uint32_t>& count = counts_;
  count.resize(kBuckets);
  for (unsigned shift = 0; (differing >> shift) != 0; shift += kDigitBits) {
    std::fill(count.begin(), count.end(), 0u);
    for (const SortItem& it : items_) ++count[(it.code >> shift) & (kBuckets - 1)];
    uint32_t sum = 0;
    for (uint32_t& c : count) {
      const uint32_t here = c;
      c = sum;
      sum += here;
    }
    for (const SortItem& it : items_) scratch_[count[(it.code >> shift) & (kBuckets - 1)]++] = it;
    items_.swap(scratch_);
  }
  sorted_.clear();
  sorted_.reserve(n);
  for (const SortItem& it : items_) {
    const VoxelUpdate& u = updates[it.index];
    if (sorted_.empty() || sorted_.back().morton != u.morton) sorted_.push_back(u);
  }
  updates.swap(sorted_);
}

// Both lists are sorted: one merge. A voxel in both keeps the update of `updates` (its kind is
// at least as strong as free).
inline void OctreeBatch::mergeFree(std::vector<VoxelUpdate>& updates, const std::vector<octomap::OcTreeKey>& sortedFree) {
  if (sortedFree.empty()) return;
  sorted_.clear();
  sorted_.reserve(updates.size() + sortedFree.size());
  auto a = updates.begin();
  for (const octomap::OcTreeKey& k : sortedFree) {
    VoxelUpdate f;
    f.key = k;
    f.morton = mortonCode(k);
    while (a != updates.end() && a->morton < f.morton) sorted_.push_back(*a++);
    if (a != updates.end() && a->morton == f.morton) continue;
    sorted_.push_back(f);
  }
  sorted_.insert(sorted_.end(), a, updates.end());
  updates.swap(sorted_);
}

// The end of the run of updates from b on whose code starts with `prefix` (the updates of one
// child). Galloping, then a binary search: near the root one child holds all of a node's
// voxels, and a scan there would visit every update at every level (16 times each).
inline VoxelUpdate* OctreeBatch::runEnd(VoxelUpdate* b, VoxelUpdate* end, unsigned shift, uint64_t prefix) {
  auto inRun = [&](const VoxelUpdate& u) { return (u.morton >> shift) == prefix; };
  size_t step = 1;
  VoxelUpdate* lo = b + 1;  // every update before lo is in the run
  while (step <= size_t(end - lo) && inRun(lo[step - 1])) {
    lo += step;
    step *= 2;
  }
  VoxelUpdate* hi = lo + std::min(step, size_t(end - lo));  // the run ends in [lo, hi]
  return std::partition_point(lo, hi, inRun);
}

inline void OctreeBatch::descend(octomap::ColorOcTreeNode* node, unsigned depth, bool created, VoxelUpdate* begin,
                                 VoxelUpdate* end) {
  octomap::ColorOcTree& tree = *tree_;
  const unsigned treeDepth = tree.getTreeDepth();
  if (depth == treeDepth) {  // one update per voxel (sortByVoxel)
    // OccupancyOcTreeBase::updateNodeLogOdds, inline (its addValue is a library call).
    const float l = node->getLogOdds() + (begin->kind == VoxelUpdate::kFree ? miss_ : hit_);
    node->setLogOdds(l < clampMin_ ? clampMin_ : (l > clampMax_ ? clampMax_ : l));
    if (begin->hasColor) {
      if (node->isColorSet()) {  // white is "not set" in ColorOcTree
        const octomap::ColorOcTreeNode::Color c = node->getColor();
        node->setColor(uint8_t((c.r + begin->r) / 2), uint8_t((c.g + begin->g) / 2), uint8_t((c.b + begin->b) / 2));
      } else {
        node->setColor(begin->r, begin->g, begin->b);
      }
    }
    return;
  }
  // A leaf above the bottom that this descent did not create is a pruned block: split it.
  if (!created && !tree.nodeHasChildren(node)) tree.expandNode(node);
  // The descent is bound by cache misses on nodes scattered over the heap: ask for all the
  // children at once, so that their misses overlap instead of coming one after the other.
  if (!created) {
    for (unsigned i = 0; i < 8; ++i) {
      if (tree.nodeChildExists(node, i)) __builtin_prefetch(tree.getNodeChild(node, i));
    }
  }
  // The Morton code holds the child index of every level: 3 bits per level, root first.
  const unsigned shift = 3 * (treeDepth - 1 - depth);
  for (VoxelUpdate* b = begin; b != end;) {
    const uint64_t prefix = b->morton >> shift;
    const unsigned child = static_cast<unsigned>(prefix) & 7u;
    VoxelUpdate* e = runEnd(b, end, shift, prefix);
    bool newChild = false;
    if (!tree.nodeChildExists(node, child)) {
      tree.createNodeChild(node, child);
      newChild = true;
    }
    descend(tree.getNodeChild(node, child), depth + 1, newChild, b, e);
    b = e;
  }
  updateFromChildren(tree, node);
}

// ColorOcTreeNode's updateOccupancyChildren (the children's maximum log-odds) and, for coloured
// maps, updateColorChildren (the integer mean of the children's set colours, white when none
// is set), in one pass over the children instead of two library calls.
inline void OctreeBatch::updateFromChildren(const octomap::ColorOcTree& tree, octomap::ColorOcTreeNode* node) const {
  float maxLogOdds = -std::numeric_limits<float>::max();
  int r = 0, g = 0, b = 0, colored = 0;
  for (unsigned i = 0; i < 8; ++i) {
    if (!tree.nodeChildExists(node, i)) continue;
    const octomap::ColorOcTreeNode* c = tree.getNodeChild(node, i);
    maxLogOdds = std::max(maxLogOdds, c->getLogOdds());
    if (colors_ && c->isColorSet()) {
      const octomap::ColorOcTreeNode::Color col = c->getColor();
      r += col.r;
      g += col.g;
      b += col.b;
      ++colored;
    }
  }
  node->setLogOdds(maxLogOdds);
  if (!colors_) return;
  if (colored > 0) node->setColor(uint8_t(r / colored), uint8_t(g / colored), uint8_t(b / colored));
  else node->setColor(255, 255, 255);
}

}  // namespace rtabmap::maps_detail

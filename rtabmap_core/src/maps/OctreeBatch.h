#pragma once
// One node's voxel updates applied to an OcTree in one descent. OcTree::updateNode walks the 16
// levels from the root for every voxel; a node's voxels are neighbours, so sorted in the tree's
// child order (the Morton code of their keys) they share most of that walk. The descent also
// refreshes the inner nodes it passed (maximum of the children, as updateInnerOccupancy does,
// and their mean colour), so no whole-tree pass is needed after it. Same values as updateNode
// with lazy evaluation followed by updateInnerOccupancy: new voxels start at log-odds 0, each
// update adds its log-odds and clamps. Internal to the maps area.
#include <octomap/ColorOcTree.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rtabmap::maps_detail {

struct VoxelUpdate {
  enum Kind : uint8_t { kObstacle = 0, kGround = 1, kFree = 2 };  // priority order
  uint64_t morton = 0;
  octomap::OcTreeKey key;
  Kind kind = kFree;
  bool hasColor = false;  // occupied voxels of a coloured grid
  uint8_t r = 0, g = 0, b = 0;
};

// Child index of a key at a bit level, as OcTree numbers children.
inline unsigned childIndex(const octomap::OcTreeKey& k, unsigned level) {
  return ((k[0] >> level) & 1u) | (((k[1] >> level) & 1u) << 1) | (((k[2] >> level) & 1u) << 2);
}

inline uint64_t mortonCode(const octomap::OcTreeKey& k) {
  uint64_t code = 0;
  for (int level = 15; level >= 0; --level) code = (code << 3) | childIndex(k, static_cast<unsigned>(level));
  return code;
}

class OctreeBatch {
 public:
  explicit OctreeBatch(octomap::ColorOcTree& tree) : tree_(tree) {}

  // Applies one node's updates: hit for obstacle and ground voxels, miss for free ones, each
  // voxel once, the strongest kind winning (obstacle, then ground, then free: a voxel this node
  // saw occupied is not freed by its own rays). Leaves `updates` sorted and without duplicates.
  void apply(std::vector<VoxelUpdate>& updates, float hit, float miss) {
    if (updates.empty()) return;
    colors_ = false;
    for (VoxelUpdate& u : updates) {
      u.morton = mortonCode(u.key);
      colors_ = colors_ || u.hasColor;
    }
    std::sort(updates.begin(), updates.end(), [](const VoxelUpdate& a, const VoxelUpdate& b) {
      return a.morton < b.morton || (a.morton == b.morton && a.kind < b.kind);
    });
    updates.erase(std::unique(updates.begin(), updates.end(),
                              [](const VoxelUpdate& a, const VoxelUpdate& b) { return a.morton == b.morton; }),
                  updates.end());
    hit_ = hit;
    miss_ = miss;
    if (!tree_.getRoot()) {
      // The root is private to the tree: let it create the root (and a path, at log-odds 0, the
      // value any new voxel starts from) with a null update.
      tree_.updateNode(updates.front().key, 0.0f, true);
    }
    descend(tree_.getRoot(), 0, false, updates.data(), updates.data() + updates.size());
  }

 private:
  void descend(octomap::ColorOcTreeNode* node, unsigned depth, bool created, VoxelUpdate* begin, VoxelUpdate* end) {
    const unsigned treeDepth = tree_.getTreeDepth();
    if (depth == treeDepth) {
      for (VoxelUpdate* u = begin; u != end; ++u) {
        tree_.updateNodeLogOdds(node, u->kind == VoxelUpdate::kFree ? miss_ : hit_);
        if (u->hasColor) {
          if (node->isColorSet()) {  // white is "not set" in ColorOcTree
            const octomap::ColorOcTreeNode::Color c = node->getColor();
            node->setColor(uint8_t((c.r + u->r) / 2), uint8_t((c.g + u->g) / 2), uint8_t((c.b + u->b) / 2));
          } else {
            node->setColor(u->r, u->g, u->b);
          }
        }
      }
      return;
    }
    // A leaf above the bottom that this descent did not create is a pruned block: split it.
    if (!created && !tree_.nodeHasChildren(node)) tree_.expandNode(node);
    // The Morton code holds the child index of every level: 3 bits per level, root first.
    const unsigned shift = 3 * (treeDepth - 1 - depth);
    for (VoxelUpdate* b = begin; b != end;) {
      const unsigned child = static_cast<unsigned>(b->morton >> shift) & 7u;
      const uint64_t prefix = b->morton >> shift;
      VoxelUpdate* e = b + 1;
      while (e != end && (e->morton >> shift) == prefix) ++e;
      bool newChild = false;
      if (!tree_.nodeChildExists(node, child)) {
        tree_.createNodeChild(node, child);
        newChild = true;
      }
      descend(tree_.getNodeChild(node, child), depth + 1, newChild, b, e);
      b = e;
    }
    node->updateOccupancyChildren();
    if (colors_) node->updateColorChildren();
  }

  octomap::ColorOcTree& tree_;
  bool colors_ = false;
  float hit_ = 0.0f, miss_ = 0.0f;
};

}  // namespace rtabmap::maps_detail

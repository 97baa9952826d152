#pragma once
// What the SLAM pipeline knows of every node, in RAM or in the long-term memory: its map (the
// session that created it), its last optimised pose, and which maps are merged into one
// referential (Labbé & Michaud, "Online global loop closure detection for large-scale
// multi-session graph-based SLAM", IROS 2014): two maps are merged as soon as one link joins
// them, and stay merged while one does (a wrong merge can be undone, see MergeArbiter). The
// global map and the trajectory span the maps merged with the
// current one; a map never linked to the current one is a separate referential.
//
// A few dozen bytes per node, so it holds the whole database: the local optimisation only
// moves the nodes in RAM, the others keep the pose they had when they left.
#include <map>
#include <set>
#include <utility>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

class SessionGraph {
 public:
  // Adds or moves a node (a null pose keeps the node known without a pose).
  void setPose(int id, int mapId, const Transform& pose);
  // Moves nodes already known (unknown ids are ignored).
  void updatePoses(const std::map<int, Transform>& poses);
  void erase(int id);
  void clear();

  bool contains(int id) const { return nodes_.count(id) != 0; }
  // Null if unknown.
  Transform pose(int id) const;
  // -1 if unknown.
  int mapOf(int id) const;
  // A link joins these two maps: one referential from now on (nothing when they are the same).
  void mergeMaps(int mapA, int mapB);
  // A link that joined them is gone: they part when it was the last one joining their groups.
  void unmergeMaps(int mapA, int mapB);
  // The representative of a map's group (the smallest map id merged with it).
  int groupOf(int mapId) const;
  bool sameGroup(int mapA, int mapB) const { return groupOf(mapA) == groupOf(mapB); }
  // Maps merged with this one, itself included.
  std::set<int> mapsMergedWith(int mapId) const;
  // Nodes with a pose whose map is merged with `mapId`.
  std::map<int, Transform> posesOfGroup(int mapId) const;
  // Every node with a pose.
  std::map<int, Transform> poses() const;
  // Some node with a pose belongs to another map than `mapId` (stops at the first one).
  bool hasPoseOutside(int mapId) const;
  size_t size() const { return nodes_.size(); }

 private:
  struct Node {
    int mapId = -1;
    Transform pose;
  };
  std::map<int, Node> nodes_;
  void unite(int mapA, int mapB);

  std::map<int, int> parent_;                 // union-find over map ids
  std::map<std::pair<int, int>, int> joins_;  // links joining two maps (smaller id first)
};

}  // namespace rtabmap

#include "rtabmap_core/slam/SessionGraph.h"

namespace rtabmap {

void SessionGraph::setPose(int id, int mapId, const Transform& pose) {
  Node& n = nodes_[id];
  n.mapId = mapId;
  n.pose = pose;
  parent_.emplace(mapId, mapId);
}

void SessionGraph::updatePoses(const std::map<int, Transform>& poses) {
  for (const auto& [id, pose] : poses) {
    auto it = nodes_.find(id);
    if (it != nodes_.end()) it->second.pose = pose;
  }
}

void SessionGraph::erase(int id) { nodes_.erase(id); }

void SessionGraph::clear() {
  nodes_.clear();
  parent_.clear();
  joins_.clear();
}

Transform SessionGraph::pose(int id) const {
  auto it = nodes_.find(id);
  return it == nodes_.end() ? Transform() : it->second.pose;
}

int SessionGraph::mapOf(int id) const {
  auto it = nodes_.find(id);
  return it == nodes_.end() ? -1 : it->second.mapId;
}

int SessionGraph::groupOf(int mapId) const {
  auto it = parent_.find(mapId);
  while (it != parent_.end() && it->second != it->first) it = parent_.find(it->second);
  return it == parent_.end() ? mapId : it->first;
}

void SessionGraph::mergeMaps(int mapA, int mapB) {
  if (mapA == mapB) return;
  ++joins_[std::minmax(mapA, mapB)];
  unite(mapA, mapB);
}

void SessionGraph::unmergeMaps(int mapA, int mapB) {
  auto it = joins_.find(std::minmax(mapA, mapB));
  if (it == joins_.end()) return;
  if (--it->second > 0) return;
  joins_.erase(it);
  // Union-find cannot split: the groups are rebuilt from the joins left.
  for (auto& [m, parent] : parent_) parent = m;
  for (const auto& [maps, count] : joins_) unite(maps.first, maps.second);
}

void SessionGraph::unite(int mapA, int mapB) {
  parent_.emplace(mapA, mapA);
  parent_.emplace(mapB, mapB);
  const int a = groupOf(mapA), b = groupOf(mapB);
  if (a == b) return;
  // The smaller map id represents the group: the oldest session's referential.
  if (a < b) {
    parent_[b] = a;
  } else {
    parent_[a] = b;
  }
}

std::set<int> SessionGraph::mapsMergedWith(int mapId) const {
  std::set<int> maps;
  const int group = groupOf(mapId);
  for (const auto& [m, parent] : parent_) {
    (void)parent;
    if (groupOf(m) == group) maps.insert(m);
  }
  maps.insert(mapId);
  return maps;
}

std::map<int, Transform> SessionGraph::posesOfGroup(int mapId) const {
  const std::set<int> maps = mapsMergedWith(mapId);
  std::map<int, Transform> out;
  for (const auto& [id, n] : nodes_) {
    if (!n.pose.isNull() && maps.count(n.mapId)) out.emplace_hint(out.end(), id, n.pose);
  }
  return out;
}

bool SessionGraph::hasPoseOutside(int mapId) const {
  for (const auto& [id, n] : nodes_) {
    if (!n.pose.isNull() && n.mapId != mapId) return true;
  }
  return false;
}

std::map<int, Transform> SessionGraph::poses() const {
  std::map<int, Transform> out;
  for (const auto& [id, n] : nodes_) {
    if (!n.pose.isNull()) out.emplace_hint(out.end(), id, n.pose);
  }
  return out;
}

}  // namespace rtabmap

#include "rtabmap_slam_node/MapsHandover.h"

namespace rtabmap_slam_node {
namespace {

bool usablePose(const rtabmap::Transform& pose) { return !pose.isNull() && !pose.isInvalid(); }

// A map wanted now that was not at the last job: it starts from every node's grid.
bool gained(const MapsWanted& now, const MapsWanted& before) {
  return (now.cloud && !before.cloud) || (now.octomap && !before.octomap) || (now.grid && !before.grid);
}

}  // namespace

rtabmap::LocalGrid deepCopy(const rtabmap::LocalGrid& grid) {
  rtabmap::LocalGrid copy = grid;
  copy.ground = grid.ground.clone();
  copy.obstacles = grid.obstacles.clone();
  copy.empty = grid.empty.clone();
  return copy;
}

std::optional<MapsJob> MapsHandover::makeJob(std::map<int, rtabmap::Transform> poses, const MapsWanted& wanted,
                                             bool force, const MapsAssembler::GridSource& source) {
  if (!wanted.any()) {
    // The worker drops the maps (and the grids it holds) once; after that, nothing to do.
    // Invalidations are kept for the next job that wants a map: the worker's assembler remembers
    // the nodes that had no grid, and must hear that they have one now.
    const bool dropMaps = lastWanted_.any();
    handed_.clear();
    lastWanted_ = wanted;
    if (!dropMaps) return std::nullopt;
    MapsJob job;
    job.wanted = wanted;
    return job;
  }
  if (gained(wanted, lastWanted_)) handed_.clear();  // a full snapshot
  MapsJob job;
  for (const auto& [id, pose] : poses) {
    if (!usablePose(pose) || handed_.count(id)) continue;
    std::optional<rtabmap::LocalGrid> grid = source ? source(id) : std::nullopt;
    if (grid && grid->isEmpty()) grid.reset();
    job.grids.emplace(id, grid ? std::optional<rtabmap::LocalGrid>(deepCopy(*grid)) : std::nullopt);
    handed_.insert(id);
  }
  job.invalidated = std::move(invalidated_);
  invalidated_.clear();
  job.poses = std::move(poses);
  job.wanted = wanted;
  job.force = force;
  lastWanted_ = wanted;
  return job;
}

void MapsHandover::invalidate(int nodeId) {
  handed_.erase(nodeId);
  invalidated_.insert(nodeId);
}

void MapsHandover::clear() {
  handed_.clear();
  invalidated_.clear();
  lastWanted_ = MapsWanted();
}

}  // namespace rtabmap_slam_node

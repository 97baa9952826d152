#pragma once
// The owner's side of the maps worker (MapsWorker.h): what the SLAM nodelet or map_assembler
// hands over at an update, made under its own lock, so it must be cheap. It remembers which
// nodes' local grids the worker already received, so a job carries the graph's poses and the
// grids of new (or invalidated) nodes only: one grid per update in steady state. Everything is
// handed again (a full snapshot) only when a map becomes wanted (a new subscriber: the map is
// built from the whole graph) and after clear(). Nothing wanted: no job at all, except one that
// lets the worker drop the maps nobody listens to any more.
#include <optional>
#include <set>

#include "rtabmap_slam_node/MapsWorker.h"

namespace rtabmap_slam_node {

class MapsHandover {
 public:
  // The job of this update, or nullopt when there is nothing to do (nothing wanted, now and at
  // the last job). `source` is asked only for the grids to hand over; they are deep copies, so
  // the worker never shares pixels with the owner's data.
  std::optional<MapsJob> makeJob(std::map<int, rtabmap::Transform> poses, const MapsWanted& wanted, bool force,
                                 const MapsAssembler::GridSource& source);
  // The node's grid changed: handed again, and the maps drop the old one, at the next job.
  void invalidate(int nodeId);
  // The worker was cleared: nothing was handed over.
  void clear();
  size_t handedCount() const { return handed_.size(); }

 private:
  std::set<int> handed_;       // nodes whose grid (or lack of one) the worker received
  std::set<int> invalidated_;  // since the last job
  MapsWanted lastWanted_;      // of the last job
};

// A copy owning its cells.
rtabmap::LocalGrid deepCopy(const rtabmap::LocalGrid& grid);

}  // namespace rtabmap_slam_node

#pragma once
// Fuzz entries of the pose-graph files (optimizer/GraphIO.h) and the trajectory files
// (eval/Trajectory.h).
#include <sstream>

#include "FuzzEntry.h"
#include "rtabmap_core/eval/Trajectory.h"
#include "rtabmap_core/optimizer/GraphIO.h"

namespace rtabmap::fuzz {

inline Outcome fuzzG2o(const uint8_t* data, size_t size) {
  return guarded([&] {
    std::istringstream in(asText(data, size));
    const graph::PoseGraphFile file = graph::parseG2o(in, "fuzz.g2o");
    // What was accepted must be writable (the writer meets every value the reader let in).
    std::ostringstream out;
    graph::formatG2o(out, file.poses, file.links, file.is2D);
  });
}

inline Outcome fuzzToro(const uint8_t* data, size_t size) {
  return guarded([&] {
    std::istringstream in(asText(data, size));
    const graph::PoseGraphFile file = graph::parseToro(in, "fuzz.graph");
    std::ostringstream out;
    graph::formatToro(out, file.poses, file.links, file.is2D);
  });
}

// TUM, KITTI, g2o-vertex or EuRoC trajectories, told apart by content (format detection is
// part of what is fuzzed); an accepted trajectory is then sorted and interpolated.
inline Outcome fuzzTrajectory(const uint8_t* data, size_t size) {
  const std::string path = writeScratchFile(data, size, ".txt");
  return guarded([&] {
    Trajectory t = readTrajectory(path, TrajectoryFormat::kAuto);
    t.sortByStamp();
    t.pathLength();
    if (!t.empty()) t.interpolate((t.poses.front().stamp + t.poses.back().stamp) / 2.0);
  });
}

}  // namespace rtabmap::fuzz

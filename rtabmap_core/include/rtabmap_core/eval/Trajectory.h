#pragma once
// A trajectory: poses with their stamps, as ground-truth and estimate files hold them, and the
// readers and writers of the usual file formats.
//
//   tum    one pose per line: `stamp x y z qx qy qz qw` (blank- or comma-separated); lines
//          starting with '#' are comments (TUM RGB-D benchmark).
//   kitti  one pose per line: the 12 values of the 3x4 matrix [R | t], row-major (KITTI
//          odometry). No stamps: row n (0-based) gets stamp n.
//   g2o    the vertices of a g2o graph: `VERTEX_SE2 id x y theta` and
//          `VERTEX_SE3:QUAT id x y z qx qy qz qw`; every other line (edges, FIX, ...) is
//          skipped. No stamps: a vertex gets its id as stamp. Written as VERTEX_SE3:QUAT, with
//          the stamps as ids when they are all integers, else the row index.
//   euroc  (read only) EuRoC's state_groundtruth_estimate0/data.csv: `stamp_ns, px, py, pz,
//          qw, qx, qy, qz, ...` (further columns ignored).
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

struct StampedPose {
  double stamp = 0.0;  // seconds (or an index for formats without time)
  Transform pose;
};

struct Trajectory {
  std::vector<StampedPose> poses;

  size_t size() const { return poses.size(); }
  bool empty() const { return poses.empty(); }
  const StampedPose& operator[](size_t i) const { return poses[i]; }
  void add(double stamp, const Transform& pose) { poses.push_back({stamp, pose}); }

  // True if stamps never decrease.
  bool isSorted() const;
  // Stable sort by stamp (keeps the file order of equal stamps).
  void sortByStamp();
  // Index of the pose whose stamp is nearest to `stamp`, if it is at most maxDifference away;
  // -1 otherwise. Needs a sorted trajectory (std::logic_error if not).
  long nearest(double stamp, double maxDifference) const;
  // The pose at `stamp`: an exact stamp (within 1 ns) gives its pose; otherwise the poses just
  // before and after are interpolated (linear in translation, slerp in rotation) if they are at
  // most maxGap seconds apart. Null outside the trajectory, across a larger gap, or when a
  // bracketing pose is null. Needs a sorted trajectory.
  Transform interpolate(double stamp,
                        double maxGap = std::numeric_limits<double>::infinity()) const;
  // Sum of the distances between consecutive non-null poses.
  double pathLength() const;
  std::vector<Transform> transforms() const;
  std::vector<double> stamps() const;
};

enum class TrajectoryFormat { kAuto, kTum, kKitti, kG2o, kEuroc };

// "tum", "kitti", "g2o", "euroc", "auto" <-> enum; FormatError on another name.
TrajectoryFormat trajectoryFormatFromName(const std::string& name);
std::string trajectoryFormatName(TrajectoryFormat format);
// The format of a file from its content: the first line that is not blank or a comment
// (VERTEX_/EDGE_ -> g2o, 12 numbers -> kitti, 8 numbers -> tum, a comma-separated line of at
// least 8 numbers starting with an integer nanosecond stamp -> euroc). FormatError naming the
// file when it fits none.
TrajectoryFormat detectTrajectoryFormat(const std::string& path);

// Reads a trajectory file (kAuto: detectTrajectoryFormat). Poses keep the file's order.
// Throws FormatError "file:line: ..." on a malformed line, and when the file cannot be opened
// or holds no pose.
Trajectory readTrajectory(const std::string& path, TrajectoryFormat format = TrajectoryFormat::kAuto);
// Writes with full precision (every value reads back to the same double). Null poses are
// skipped. Throws Error when the file cannot be written, FormatError for kAuto / kEuroc.
void writeTrajectory(const std::string& path, const Trajectory& trajectory, TrajectoryFormat format);

}  // namespace rtabmap

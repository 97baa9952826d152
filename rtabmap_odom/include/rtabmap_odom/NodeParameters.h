#pragma once
// The odometry nodes' private parameters, without ROS plumbing (unit-tested without a master):
//  - core parameters given with their "Group/Name" keys (as in the classic launch files:
//    <param name="Odom/Strategy" type="string" value="1"/>), validated by the core's registry;
//    an unknown key or an invalid value is reported (with the closest declared key) and
//    ignored, so a typo in a launch file never stops the node but never goes unnoticed either;
//  - the node's own parameters, whose misspellings get the same "did you mean" treatment;
//  - icp_odometry's scan options, turned into the core's Icp/ parameters.
#include <map>
#include <string>
#include <vector>

#include "rtabmap_core/params/Parameters.h"

namespace rtabmap_odom {

struct CoreParameters {
  rtabmap::ParametersMap parameters;  // declared keys with valid values
  std::vector<std::string> warnings;  // one line per ignored entry, naming the key
};

// `raw`: private parameter names relative to the node ("Odom/Strategy", "frame_id") -> value as
// text. Names with a '/' are core keys; the others are the node's own and are left out here.
CoreParameters coreParametersFromPrivate(const std::map<std::string, std::string>& raw);

// Warnings for the names without a '/' that are not in `known` (the node's parameters), each
// naming the closest known one.
std::vector<std::string> unknownNodeParameters(const std::map<std::string, std::string>& raw,
                                               const std::vector<std::string>& known);

// icp_odometry's classic scan parameters.
struct ScanOptions {
  double rangeMin = 0.0;      // scan_range_min (m, 0 = none): points closer are dropped
  double rangeMax = 0.0;      // scan_range_max (m, 0 = none): points farther are dropped
  double voxelSize = 0.0;     // scan_voxel_size (m, 0 = keep the core's Icp/VoxelSize)
  int downsamplingStep = 1;   // scan_downsampling_step (1 = keep the core's Icp/DownsamplingStep)
  int normalK = 0;            // scan_normal_k (0 = keep the core's Icp/PointToPlaneK)
  double normalRadius = 0.0;  // scan_normal_radius (0 = keep the core's Icp/PointToPlaneRadius)
  // False with the reason (naming the parameter) for negative values or min >= max.
  bool IsValid(std::string* why = nullptr) const;
};

// The core's ICP prepares every scan itself (range limits, one point in N, voxel grid, normals
// when point-to-plane) and S2M builds its map from the prepared scans, so the scan options are
// those steps' Icp/ parameters: scan_voxel_size -> Icp/VoxelSize, scan_downsampling_step ->
// Icp/DownsamplingStep, scan_normal_k -> Icp/PointToPlaneK, scan_normal_radius ->
// Icp/PointToPlaneRadius, scan_range_min|max -> Icp/RangeMin|Max. A key the user also set as a
// core parameter keeps the user's value, with a note in *notes. Returns the merged map.
rtabmap::ParametersMap applyScanOptions(const ScanOptions& options, const rtabmap::ParametersMap& parameters,
                                        std::vector<std::string>* notes = nullptr);

}  // namespace rtabmap_odom

#pragma once
// sensor_msgs/LaserScan <-> rtabmap::LaserScan (planar scans).
//
// The core keeps a planar scan as points (XY, or XYI with intensities) plus the beam geometry
// (angle_min, angle_max, angle_increment), so beams without a return are not lost: they come
// back as +Inf ranges (REP-117 "no return"), and the 2D grid still ray-traces them as free
// space. Beams that are NaN, infinite, or outside [range_min, range_max] are dropped from the
// points. Ranges travel as float32 x, y (r cos a, r sin a), so a range comes back within a few
// float ulps, not bit-exact.
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/Header.h>

#include <optional>
#include <string>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_conversions {

// localTransform: base frame -> laser frame (header.frame_id), usually from tf. Errors: NaN
// or zero angle increment, angles that disagree with the number of ranges, no ranges, invalid
// range limits, intensities that do not match the ranges.
std::optional<rtabmap::LaserScan> laserScanFromMsg(const sensor_msgs::LaserScan& msg,
                                                   const rtabmap::Transform& localTransform = rtabmap::Transform::Identity(),
                                                   std::string* error = nullptr);
// The message of a planar scan with beam geometry (in the sensor frame, header.frame_id).
// Errors: a 3D scan, or a scan built from points (no beam geometry: which beam is which is
// unknown; publish it as a PointCloud2 instead).
std::optional<sensor_msgs::LaserScan> laserScanToMsg(const rtabmap::LaserScan& scan, const std_msgs::Header& header,
                                                     std::string* error = nullptr);

}  // namespace rtabmap_conversions

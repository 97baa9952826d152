#pragma once
// sensor_msgs/PointCloud2 <-> rtabmap::LaserScan (3D lidar clouds, and any cloud a node turns
// into a scan).
//
// Reading: x, y, z are required (float32 or float64, or any numeric type); the scan format
// follows the other fields present: "intensity" (or "i") -> XYZI, "rgb" / "rgba" -> XYZRGB,
// normal_x/normal_y/normal_z -> ...Normal. A cloud with both intensity and colour keeps the
// intensity (a lidar's). Points with a non-finite x, y or z are dropped (organised clouds mark
// holes with NaN); maxPoints is the cloud's width * height, so the fraction kept stays known.
//
// Writing: one float32 field per channel, named as PCL names them (x y z intensity rgb
// normal_x normal_y normal_z), packed, little-endian, unorganised (height 1). Planar formats
// (XY...) are written with z = 0, so they come back as the matching XYZ format; 3D formats
// round-trip bit-exactly.
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>

#include <optional>
#include <string>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_conversions {

// localTransform: base frame -> cloud frame (header.frame_id). rangeMin / rangeMax are the
// sensor's limits recorded in the scan (0 = unknown); they do not filter. Errors: no x, y or z
// field, fields or points that lie outside the data, a big-endian cloud.
std::optional<rtabmap::LaserScan> laserScanFromCloudMsg(
    const sensor_msgs::PointCloud2& msg, const rtabmap::Transform& localTransform = rtabmap::Transform::Identity(),
    std::string* error = nullptr, double rangeMin = 0.0, double rangeMax = 0.0);

// The scan's points in its own (sensor) frame.
sensor_msgs::PointCloud2 laserScanToCloudMsg(const rtabmap::LaserScan& scan, const std_msgs::Header& header);

}  // namespace rtabmap_conversions

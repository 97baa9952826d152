#pragma once
// Odom/AlignWithGround: a hand-held or tilted camera's base frame is not level, so neither is
// an odometry that starts at the identity, nor the map and grids built on it. At its first frame
// odometry starts instead level with the floor that frame sees, at the base's height above it.
// Private to the odometry area.
#include <string>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap::odometry_detail {

// The base's pose in a frame level with the floor seen in `data` (its depth image, stereo pair,
// or 3D scan; maps/GroundPlane.h): roll and pitch from the floor's normal, z its height above
// the floor, x, y and (nearly) yaw 0. Null, with the reason in *why, when no floor is found.
Transform groundAlignedPose(const SensorData& data, std::string* why);

}  // namespace rtabmap::odometry_detail

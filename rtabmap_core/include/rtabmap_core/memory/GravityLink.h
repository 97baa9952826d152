#pragma once
// The gravity constraint of a new node: a kGravity link from the node to itself holding the
// node's orientation in a gravity-aligned world frame (Optimizer/GravitySigma > 0 makes the
// graph optimiser keep each node's up axis there; only roll and pitch count, the heading stays
// free). Where that orientation comes from:
//  - Mem/UseOdomGravity: the odometry pose itself, for odometry that is already aligned with
//    gravity (visual-inertial odometry, an IMU-fused filter);
//  - else the frame's IMU orientation (sensor_msgs/Imu with an orientation, e.g. from a
//    Madgwick filter), brought from the IMU's frame to the robot's base.
#include <optional>

#include "rtabmap_core/geometry/IMU.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap::memory {

// The gravity link of node `id` with odometry pose `odomPose`, if it has one: none for a node
// without a pose (appearance only), or without an orientation from the chosen source.
std::optional<Link> gravityLinkOf(int id, const Transform& odomPose, const IMU& imu, bool useOdomGravity);

}  // namespace rtabmap::memory

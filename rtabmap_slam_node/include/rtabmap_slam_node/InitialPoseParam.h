#pragma once
// The rtabmap node's initial_pose parameter (classic rtabmap_ros form): where the robot is in
// the map frame when the node starts or switches mode, as text.
#include <optional>
#include <string>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_slam_node {

// "x y z roll pitch yaw" (metres, radians), or "x y z qx qy qz qw" (the quaternion is
// normalised); spaces or commas between the values. "" (or blanks only): nullopt and *why
// empty (no initial pose). Anything else (another count, a value that is not a finite
// number, a zero quaternion): nullopt with the reason in *why.
std::optional<rtabmap::Transform> parseInitialPose(const std::string& text, std::string* why);

}  // namespace rtabmap_slam_node

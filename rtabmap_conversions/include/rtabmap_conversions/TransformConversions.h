#pragma once
// Rigid transforms between the core (rtabmap::Transform) and ROS (geometry_msgs, tf2).
// A null Transform ("no pose") has no ROS equivalent: converting one gives the all-zero
// message (invalid quaternion), which transformFromMsg turns back into a null Transform, so
// "lost" survives a round trip through a message.
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>
#include <geometry_msgs/TransformStamped.h>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_conversions {

geometry_msgs::Transform transformToMsg(const rtabmap::Transform& transform);
rtabmap::Transform transformFromMsg(const geometry_msgs::Transform& msg);
geometry_msgs::Pose transformToPoseMsg(const rtabmap::Transform& transform);
rtabmap::Transform transformFromPoseMsg(const geometry_msgs::Pose& msg);

}  // namespace rtabmap_conversions

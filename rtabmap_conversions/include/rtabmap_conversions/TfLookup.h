#pragma once
// tf lookups for callbacks: wait a bounded time for a transform, and on failure return a null
// Transform with a message that names the frames and what tf said, instead of throwing.
//
// Waiting polls the buffer (every 5 ms, wall clock) rather than using tf2_ros's blocking
// canTransform: that one refuses to wait on a buffer without a dedicated listener thread and
// follows the ROS clock, which stands still when a bag is paused. A callback thus never blocks
// longer than wait_for_transform_duration, whatever the clock does, while a TransformListener
// thread (or another callback) fills the buffer.
#include <ros/time.h>
#include <tf2/buffer_core.h>

#include <string>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_conversions {

// The pose of sourceFrame in targetFrame at `stamp` (ros::Time(0): the latest available), i.e.
// the transform taking points of sourceFrame into targetFrame: lookupTransform(buffer,
// "base_link", "laser", ...) is the local transform of the laser. Waits up to waitSeconds (0:
// no wait) for the transform to become available. Equal frames give the identity at once.
// Failure: a null Transform and, in *error, e.g. "cannot get the transform base_link <- laser
// at t=12.345 s within 0.100 s (wait_for_transform_duration): frame 'laser' is unknown to tf".
rtabmap::Transform lookupTransform(const tf2::BufferCore& buffer, const std::string& targetFrame,
                                   const std::string& sourceFrame, const ros::Time& stamp, double waitSeconds,
                                   std::string* error = nullptr);

// The motion of `frame` from stamp `from` to stamp `to`, expressed in its own frame at `from`,
// through `fixedFrame` (e.g. the wheel odometry "odom" frame): what a guess from wheel odometry
// needs between two sensor frames. Same waiting and error rules.
rtabmap::Transform lookupMotion(const tf2::BufferCore& buffer, const std::string& fixedFrame,
                                const std::string& frame, const ros::Time& from, const ros::Time& to,
                                double waitSeconds, std::string* error = nullptr);

}  // namespace rtabmap_conversions

#pragma once
// odom_sensor_sync: with approximate synchronisation the odometry and a sensor are stamped a
// little apart, and the core places the sensor with the odometry's pose. While the robot moves,
// that misplaces the sensor by the motion between the two stamps; tf (the odometry's frame as
// the fixed frame) knows that motion, so the sensor's local transform takes it in.
#include <tf2/buffer_core.h>

#include <string>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_slam_node {

// The sensor's pose in the base frame at the odometry's stamp: motion of `baseFrame` from
// odomStamp to sensorStamp (through odomFrame) * local. Equal stamps: local, without a lookup.
// Failure (tf cannot say): a null Transform with the reason in *error.
rtabmap::Transform odomSyncedLocalTransform(const tf2::BufferCore& buffer, const std::string& odomFrame,
                                            const std::string& baseFrame, const rtabmap::Transform& local,
                                            const ros::Time& odomStamp, const ros::Time& sensorStamp,
                                            double waitSeconds, std::string* error = nullptr);

}  // namespace rtabmap_slam_node

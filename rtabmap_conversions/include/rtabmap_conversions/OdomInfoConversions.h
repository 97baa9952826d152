#pragma once
// rtabmap::OdometryInfo (one odometry update) <-> rtabmap_ros/OdomInfo (on `odom_info`).
//
// Units in the message follow the classic rtabmap_ros: times in seconds (timeEstimation),
// distances in metres, the covariance row-major 6x6. `type` is 0 for frame-to-map approaches
// (F2M, S2M) and 1 for frame-to-frame ones (F2F, S2S), as the classic message defines it.
// The registration's match / inlier feature ids fill wordMatches / wordInliers; display
// fields the core does not produce (words, local map points, corners) stay empty.
#include <rtabmap_ros/OdomInfo.h>
#include <std_msgs/Header.h>

#include <optional>
#include <string>

#include "rtabmap_core/odometry/Odometry.h"

namespace rtabmap_conversions {

rtabmap_ros::OdomInfo odomInfoToMsg(const rtabmap::OdometryInfo& info, rtabmap::Odometry::Type type,
                                    const std_msgs::Header& header);
// Errors: NaN in the covariance.
std::optional<rtabmap::OdometryInfo> odomInfoFromMsg(const rtabmap_ros::OdomInfo& msg, std::string* error = nullptr);

}  // namespace rtabmap_conversions

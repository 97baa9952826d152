#pragma once
// rtabmap::Statistics (one SLAM update) <-> rtabmap_ros/Info (published on `info`).
//
// The scalar statistics travel as parallel key / value arrays with the core's keys
// ("Timing/Total/ms", ...); maps (posterior, likelihood, weights, labels) as parallel key /
// value arrays too. The local-map poses and constraints of Statistics have their place in
// mapGraph, not in Info, and are not carried.
#include <rtabmap_ros/Info.h>
#include <std_msgs/Header.h>

#include <optional>
#include <string>

#include "rtabmap_core/slam/Statistics.h"

namespace rtabmap_conversions {

rtabmap_ros::Info statisticsToMsg(const rtabmap::Statistics& stats, const std_msgs::Header& header);
// Errors: key and value arrays of different lengths, malformed statistic keys.
std::optional<rtabmap::Statistics> statisticsFromMsg(const rtabmap_ros::Info& msg, std::string* error = nullptr);

}  // namespace rtabmap_conversions

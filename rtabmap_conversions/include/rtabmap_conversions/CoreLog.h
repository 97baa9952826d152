#pragma once
// The core library logs through a sink (rtabmap_core/common/Log.h) that writes warnings and
// errors to stderr by default. In a ROS process that would miss /rosout, rqt_console, the
// roslaunch log files and the node's name: every nodelet routes the core's log to rosconsole.

namespace rtabmap_conversions {

// Points the core's log at rosconsole, logger "ros.rtabmap_ros.core" (info and above: the core
// drops its debug messages before formatting them). Process-wide and idempotent: the first
// nodelet loaded in a manager does it, the others find it done.
void routeCoreLogToRosconsole();

}  // namespace rtabmap_conversions

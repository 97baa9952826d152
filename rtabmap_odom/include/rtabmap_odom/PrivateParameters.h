#pragma once
// What every nodelet of the package does with its private ROS parameters and its log lines
// (roscpp; compiled into the nodelet library, used by the odometry and SLAM nodelets).
#include <ros/node_handle.h>

#include <map>
#include <string>
#include <vector>

namespace rtabmap_odom {

// The node's private parameters as the text the core's parameter registry parses, names
// relative to its namespace ("Reg/Strategy"). Values with no text form (lists, structs) are
// left out; their names go to *odd when given.
std::map<std::string, std::string> privateParameters(const ros::NodeHandle& pnh,
                                                     std::vector<std::string>* odd = nullptr);

// The core parameters of the INI file ([Core] section) named by the private parameter
// config_path, as classic rtabmap_ros reads it in the odometry and SLAM nodes alike ("~/" is the
// home folder). Empty when config_path is unset or empty; then and on success *error is cleared,
// else it says why the file was ignored. *path: the file, expanded.
std::map<std::string, std::string> configFileParameters(const ros::NodeHandle& pnh, std::string* path,
                                                        std::string* error);

// The throttling key of a log line: its text without the digits (stamps and counts change, the
// problem does not), so a stream of the same problem logs once per period while a different
// problem logs at once.
std::string throttleKey(const std::string& text);

}  // namespace rtabmap_odom

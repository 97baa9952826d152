// A node that runs one nodelet of this package in its own process (the classic
// `rosrun rtabmap_ros rgbd_sync`). The nodelet keeps the node's name, namespace, private
// parameters and remappings, exactly as if loaded in a manager.
#include <nodelet/loader.h>
#include <ros/ros.h>

#include "rtabmap_core/memory/ProcessMemory.h"

#ifndef RTABMAP_NODELET_NAME
#error "RTABMAP_NODELET_NAME must name the nodelet type to load"
#endif

int main(int argc, char** argv) {
  // The allocator of a process that runs for hours (issue 10), set before ros::init starts the
  // threads that would each take an arena of their own (rtabmap's nodelet sets it again, for a
  // manager's process: the first call decides).
  rtabmap::memory::configureAllocator();
  ros::init(argc, argv, std::string(RTABMAP_NODELET_NAME).substr(std::string("rtabmap_ros/").size()));
  nodelet::Loader loader(false);  // no manager services: this process hosts one nodelet
  nodelet::V_string nargv(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), RTABMAP_NODELET_NAME, ros::names::getRemappings(), nargv)) {
    ROS_FATAL("Could not load nodelet %s. Is the workspace sourced (AMENT_PREFIX_PATH must "
              "contain its prefix; see README)?", RTABMAP_NODELET_NAME);
    return 1;
  }
  ros::spin();
  return 0;
}

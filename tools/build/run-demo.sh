#!/usr/bin/env bash
# The demo: for now, the ROS plumbing — the rgbd_sync nodelet loaded in a manager, standalone
# and as a node, turning real RGB-D frames into rtabmap_ros/RGBDImage. It grows with the SLAM
# pipeline into SLAM on bundled real data.
set -euo pipefail
ws="$1"
rostest rtabmap_ros nodelet_plumbing.test

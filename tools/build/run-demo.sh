#!/usr/bin/env bash
# make demo: RTAB-Map through the real ROS pipeline on the bundled Intel Research Lab log and on
# the simulator's multi-session robot (tools/demo/run_demo.py); writes demo_output/ and its
# report.md. Runs in the sourced catkin workspace ($1), with the system python (rospy).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
exec /usr/bin/python3 "$root/tools/demo/run_demo.py" --output "$root/demo_output" "${@:2}"

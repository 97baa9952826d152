#!/usr/bin/env bash
# make soak: hours of the simulator's long scenario through the real ROS pipeline with memory
# management on (tools/soak/run_soak.py); writes soak_output/ and its report.md, exits non-zero
# when a goal fails. Runs in the sourced catkin workspace ($1), with the system python (rospy).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
exec /usr/bin/python3 "$root/tools/soak/run_soak.py" --output "$root/soak_output" "${@:2}"

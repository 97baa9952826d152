#!/usr/bin/env bash
# Runs every test of the workspace through CTest (core gtest cases one by one, each rostest as
# one test) and ends with the summary line "N passed, N failed, N skipped".
set -uo pipefail
ws="$1"; jobs="${2:-2}"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
# catkin's setup scripts read unset variables: source them without -u.
set +u
# shellcheck disable=SC1091
source "$ws/devel/setup.bash"
set -u
results="$ws/build/test_results/ctest.xml"
mkdir -p "$(dirname "$results")" "$ROS_LOG_DIR"
ctest --test-dir "$ws/build" -j"$jobs" --output-on-failure --output-junit "$results" --timeout 900
ctest_rc=$?
/usr/bin/python3 "$here/test_summary.py" "$results"
summary_rc=$?
[[ $ctest_rc -eq 0 && $summary_rc -eq 0 ]]

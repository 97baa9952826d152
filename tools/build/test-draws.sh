#!/usr/bin/env bash
# Runs the core suites built on synthetic scenes (the rendered room, the square-loop graphs, the
# bundle-adjustment scene, the registration tests' point sets, the lidar odometry's range noise,
# the residual and transform checks' random poses, the Bayes filter's likelihoods, the grids'
# scans and noise, the ray caster's rays, the epipolar check's scenes, the simulator's materials,
# sensor noise, building and route) over other random draws of those scenes: RTABMAP_TEST_DRAW=1..N moves
# every such seed (test::drawSeed). make test runs draw 0 only; a bound that was fitted to that
# one draw, rather than to what the method guarantees, fails here on some other draw.
# Usage: test-draws.sh TEST_BIN_DIR [DRAWS]   (DRAWS defaults to 20; about 25 s per draw)
set -uo pipefail
dir="$1"; draws="${2:-20}"
# A binary, or binary:gtest_filter where most of its tests draw nothing (or take minutes).
suites=(test_features test_registration test_odometry test_optimizer test_bayes test_codec test_vocabulary
        test_geometry:'Transform.*:CameraModel.*'
        test_maps:'OctoMapVoxelBitset.*:OctoMapRayCaster.*:OccupancyGrid.*:LocalGridDepth.*'
        test_db:'DatabaseErrors.*'
        test_memory:'EpipolarCheck.*'
        test_slam:'NeighborLinkRefining.*:GlobalScanMapLocalization.*:IntermediateNodes.NeighbourLinkRefining*'
        test_sim:'SimRandom.*:SimMaterials.*:SimDecals.*:SimPng.*:SimOdometry.*:SimImu.*:SimMotion.*:SimScenarios.*:SimBuilding.*')
for s in "${suites[@]}"; do
  [[ -x "$dir/${s%%:*}" ]] || { echo "test-draws: $dir/${s%%:*} not built" >&2; exit 2; }
done
declare -A failedDraws=()
failures=0
for ((d = 1; d <= draws; ++d)); do
  for s in "${suites[@]}"; do
    bin="${s%%:*}"; filter='*'
    [[ "$s" == *:* ]] && filter="${s#*:}"
    out="$(RTABMAP_TEST_DRAW=$d "$dir/$bin" --gtest_brief=1 --gtest_filter="$filter" 2>&1)"
    rc=$?
    names="$(sed -n 's/^\[  FAILED  \] \([A-Za-z0-9_/]*\.[A-Za-z0-9_/]*\).*/\1/p' <<<"$out" | sort -u)"
    # A crash or an abort prints no FAILED line: the suite itself is then what failed.
    [[ $rc -ne 0 && -z "$names" ]] && names="$bin (exit $rc, no test reported)"
    while read -r name; do
      [[ -n "$name" ]] || continue
      failedDraws[$name]+=" $d"
      failures=$((failures + 1))
    done <<<"$names"
  done
  echo "draw $d of $draws done"
done
if [[ $failures -eq 0 ]]; then
  echo "test-draws: every test of ${suites[*]%%:*} passed on draws 1..$draws"
  exit 0
fi
echo "test-draws: tests that failed on some draw (rerun one with RTABMAP_TEST_DRAW=d):"
for name in "${!failedDraws[@]}"; do echo "  $name: draws${failedDraws[$name]}"; done | sort
exit 1

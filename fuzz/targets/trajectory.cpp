// libFuzzer target: TUM / KITTI / g2o / EuRoC trajectory files (entry: fuzzTrajectory).
#include "GraphEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzTrajectory)

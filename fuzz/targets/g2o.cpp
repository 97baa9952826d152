// libFuzzer target: g2o pose-graph files (entry: fuzzG2o).
#include "GraphEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzG2o)

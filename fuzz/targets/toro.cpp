// libFuzzer target: TORO pose-graph files (entry: fuzzToro).
#include "GraphEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzToro)

// libFuzzer target: --Group/Name command-line arguments (entry: fuzzParamsArgs).
#include "ParamsEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzParamsArgs)

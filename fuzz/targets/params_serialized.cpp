// libFuzzer target: session parameters stored in a database (entry: fuzzParamsSerialized).
#include "ParamsEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzParamsSerialized)

// libFuzzer target: parameter INI text (entry: fuzzParamsIni).
#include "ParamsEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzParamsIni)

// libFuzzer target: CARMEN logs (entry: fuzzCarmen).
#include "DataEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzCarmen)

// libFuzzer target: a mutated database file, opened and read (entry: fuzzDatabase).
#include "DataEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzDatabase)

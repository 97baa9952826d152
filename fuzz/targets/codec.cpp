// libFuzzer target: compressed blobs (images, zlib matrices, zlib bytes) (entry: fuzzCodec).
#include "DataEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzCodec)

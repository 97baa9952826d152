// libFuzzer target: sensor_msgs/PointCloud2 (entry: fuzzPointCloud2).
#include "RosEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzPointCloud2)

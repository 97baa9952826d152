// libFuzzer target: sensor_msgs/LaserScan (entry: fuzzLaserScan).
#include "RosEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzLaserScan)

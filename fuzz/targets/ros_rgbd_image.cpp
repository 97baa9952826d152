// libFuzzer target: rtabmap_ros/RGBDImage (entry: fuzzRgbdImage).
#include "RosEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzRgbdImage)

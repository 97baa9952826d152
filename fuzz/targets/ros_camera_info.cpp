// libFuzzer target: sensor_msgs/CameraInfo (mono and stereo pair) (entry: fuzzCameraInfo).
#include "RosEntries.h"
#include "FuzzTarget.h"

RTABMAP_FUZZ_TARGET(rtabmap::fuzz::fuzzCameraInfo)

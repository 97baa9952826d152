#pragma once
// A frame's images shrunk by an integer factor, with their camera models (Odom/ImageDecimation,
// Mem/ImagePreDecimation, Mem/ImagePostDecimation): colour and stereo images by area averaging,
// each camera of a side-by-side image on its own; depth by picking pixels (averaging would
// invent depths across edges), and only when it is larger than the shrunk colour image.
#include <vector>

#include "rtabmap_core/geometry/SensorData.h"

namespace rtabmap {

// The frame itself for a factor of 1 or a frame without raw images.
SensorData decimateImages(const SensorData& data, int decimation);

// Keypoints found in one image moved to the same image resized by `scale` (2 = twice as large).
void scaleKeypoints(std::vector<cv::KeyPoint>& keypoints, float scale);

}  // namespace rtabmap

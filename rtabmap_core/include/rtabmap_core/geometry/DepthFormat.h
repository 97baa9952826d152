#pragma once
// Depth images come as CV_32FC1 metres or CV_16UC1 millimetres (0 = no depth). Mem/SaveDepth16Format
// keeps nodes' depth in the second form: half the memory, and the lossless depth codec packs it
// better.
#include <opencv2/core.hpp>

namespace rtabmap {

// CV_32FC1 metres as CV_16UC1 millimetres, rounded; depths that are not finite, not positive or
// beyond 65.535 m become 0 (no depth) rather than a clamped, wrong value. Other types are
// returned unchanged.
cv::Mat depthToMillimetres(const cv::Mat& depth);

}  // namespace rtabmap

#include "rtabmap_core/geometry/DepthFormat.h"

#include <cmath>
#include <cstdint>

namespace rtabmap {

cv::Mat depthToMillimetres(const cv::Mat& depth) {
  if (depth.type() != CV_32FC1) return depth;
  cv::Mat out(depth.size(), CV_16UC1);
  for (int r = 0; r < depth.rows; ++r) {
    const float* in = depth.ptr<float>(r);
    uint16_t* o = out.ptr<uint16_t>(r);
    for (int c = 0; c < depth.cols; ++c) {
      const float mm = in[c] * 1000.0f;
      o[c] = std::isfinite(mm) && mm >= 0.5f && mm < 65535.5f ? static_cast<uint16_t>(std::lround(mm)) : 0;
    }
  }
  return out;
}

}  // namespace rtabmap

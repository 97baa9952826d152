// depthToMillimetres: float metres to 16-bit millimetres, invalid depths to 0 (not clamped).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rtabmap_core/geometry/DepthFormat.h"

namespace rtabmap {
namespace {

TEST(DepthFormat, MetresBecomeRoundedMillimetresAndInvalidDepthsNone) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const float in[] = {1.2345f, 0.0004f, 0.0f, -1.0f, nan, inf, 65.535f, 65.6f, 70.0f, 0.5f};
  const uint16_t expected[] = {1235, 0, 0, 0, 0, 0, 65535, 0, 0, 500};
  const cv::Mat depth(1, 10, CV_32FC1, const_cast<float*>(in));
  const cv::Mat mm = depthToMillimetres(depth);
  ASSERT_EQ(mm.type(), CV_16UC1);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(mm.at<uint16_t>(0, i), expected[i]) << "depth " << in[i];
}

TEST(DepthFormat, MillimetresStayAsTheyAre) {
  const cv::Mat mm(2, 2, CV_16UC1, cv::Scalar(1500));
  const cv::Mat out = depthToMillimetres(mm);
  EXPECT_EQ(out.data, mm.data);
}

}  // namespace
}  // namespace rtabmap

#pragma once
// Small helpers shared by the conversion tests.
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <tf2/buffer_core.h>

#include <cstring>
#include <random>
#include <string>

#include "rtabmap_conversions/TransformConversions.h"

namespace rtabmap_conversions::test {

// Puts parent -> child = t at `stamp` (seconds) into a tf buffer, as a broadcaster would.
inline void setTransform(tf2::BufferCore& buffer, const std::string& parent, const std::string& child,
                         const rtabmap::Transform& t, double stamp, bool isStatic) {
  geometry_msgs::TransformStamped msg;
  msg.header.frame_id = parent;
  msg.header.stamp = ros::Time(stamp);
  msg.child_frame_id = child;
  msg.transform = transformToMsg(t);
  buffer.setTransform(msg, "test", isStatic);
}

// Bit-exact equality (NaN == NaN when their bits match), with size and type.
inline ::testing::AssertionResult sameBits(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) {
    return ::testing::AssertionFailure() << "size/type differ: " << a.cols << "x" << a.rows << " type " << a.type()
                                         << " vs " << b.cols << "x" << b.rows << " type " << b.type();
  }
  const size_t rowBytes = a.cols * a.elemSize();
  for (int r = 0; r < a.rows; ++r) {
    if (std::memcmp(a.ptr(r), b.ptr(r), rowBytes) != 0) {
      return ::testing::AssertionFailure() << "row " << r << " differs";
    }
  }
  return ::testing::AssertionSuccess();
}

// A deterministic image of any type, with values spread over the type's range.
inline cv::Mat randomImage(int rows, int cols, int type, unsigned seed = 7) {
  cv::Mat m(rows, cols, type);
  cv::RNG rng(seed);
  if (CV_MAT_DEPTH(type) == CV_32F) {
    rng.fill(m, cv::RNG::UNIFORM, 0.2, 8.0);
  } else if (CV_MAT_DEPTH(type) == CV_16U) {
    rng.fill(m, cv::RNG::UNIFORM, 0, 65536);
  } else {
    rng.fill(m, cv::RNG::UNIFORM, 0, 256);
  }
  return m;
}

// A smooth colour image (jpeg-friendly), so lossy round trips can be checked tightly.
inline cv::Mat smoothImage(int rows, int cols, int channels) {
  cv::Mat m(rows, cols, CV_8UC(channels));
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      for (int k = 0; k < channels; ++k) {
        m.ptr<uint8_t>(r)[c * channels + k] = static_cast<uint8_t>((r * 2 + c * (k + 1)) % 256);
      }
    }
  }
  return m;
}

}  // namespace rtabmap_conversions::test

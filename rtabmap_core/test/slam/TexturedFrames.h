#pragma once
// Synthetic RGB-D frames for Rtabmap tests that need visual words: a 640x480 image of random
// grey blocks (corners everywhere) over a slanted plane 1.5-2.5 m away, and the same frame
// without texture (no word at all). Another seed, another texture.
#include <opencv2/imgproc.hpp>

#include "rtabmap_core/geometry/SensorData.h"

namespace rtabmap::test {

constexpr int kTexturedWidth = 640, kTexturedHeight = 480;

inline SensorData texturedFrame(int id, double stamp, bool textured = true, int seed = 7) {
  cv::Mat blocks(kTexturedHeight / 16, kTexturedWidth / 16, CV_8UC1, cv::Scalar(128));
  if (textured) {
    cv::RNG rng(static_cast<uint64_t>(seed));
    rng.fill(blocks, cv::RNG::UNIFORM, 0, 256);
  }
  cv::Mat grey, rgb;
  cv::resize(blocks, grey, cv::Size(kTexturedWidth, kTexturedHeight), 0, 0, cv::INTER_NEAREST);
  cv::cvtColor(grey, rgb, cv::COLOR_GRAY2BGR);
  cv::Mat depth(kTexturedHeight, kTexturedWidth, CV_32FC1);
  for (int u = 0; u < kTexturedWidth; ++u) depth.col(u).setTo(1.5f + static_cast<float>(u) / kTexturedWidth);
  const CameraModel model(525.0, 525.0, 319.5, 239.5, CameraModel::opticalRotation(), 0.0,
                          cv::Size(kTexturedWidth, kTexturedHeight));
  return SensorData(rgb, depth, model, id, stamp);
}

}  // namespace rtabmap::test

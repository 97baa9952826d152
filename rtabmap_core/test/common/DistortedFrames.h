#pragma once
// A raw (distorted) camera frame made from a rectified one, for the tests of
// Rtabmap/ImagesAlreadyRectified: each raw pixel takes the rectified image where the camera's
// calibration (K, D, P = [K | 0]) undistorts it to.
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "rtabmap_core/geometry/CameraModel.h"

namespace rtabmap::test {

// A 320x240 camera with strong radial distortion, its rectified projection equal to K.
inline CameraModel distortedCamera() {
  const cv::Mat K = (cv::Mat_<double>(3, 3) << 300, 0, 160, 0, 300, 120, 0, 0, 1);
  const cv::Mat D = (cv::Mat_<double>(1, 5) << -0.25, 0.06, 0.0, 0.0, 0.0);
  cv::Mat P = cv::Mat::zeros(3, 4, CV_64FC1);
  K.copyTo(P.colRange(0, 3));
  return CameraModel("distorted", cv::Size(320, 240), K, D, cv::Mat::eye(3, 3, CV_64FC1), P);
}

// The raw image the camera would have taken of `rectified` (bilinear, or nearest for depth).
inline cv::Mat distort(const cv::Mat& rectified, const CameraModel& m, int interpolation = cv::INTER_LINEAR) {
  std::vector<cv::Point2f> raw;
  for (int v = 0; v < rectified.rows; ++v) {
    for (int u = 0; u < rectified.cols; ++u) raw.emplace_back(static_cast<float>(u), static_cast<float>(v));
  }
  std::vector<cv::Point2f> rect;
  cv::undistortPoints(raw, rect, m.K_raw(), m.D_raw(), m.R(), m.P());
  cv::Mat mapX(rectified.size(), CV_32FC1), mapY(rectified.size(), CV_32FC1);
  for (size_t i = 0; i < rect.size(); ++i) {
    mapX.at<float>(static_cast<int>(i) / rectified.cols, static_cast<int>(i) % rectified.cols) = rect[i].x;
    mapY.at<float>(static_cast<int>(i) / rectified.cols, static_cast<int>(i) % rectified.cols) = rect[i].y;
  }
  cv::Mat out;
  cv::remap(rectified, out, mapX, mapY, interpolation, cv::BORDER_CONSTANT);
  return out;
}

// Blocks of random grey levels, 320x240; below, depths.
inline cv::Mat blockTexture(int seed = 3) {
  cv::Mat blocks(240 / 8, 320 / 8, CV_8UC1);
  cv::RNG rng(seed);
  rng.fill(blocks, cv::RNG::UNIFORM, 0, 256);
  cv::Mat grey, rgb;
  cv::resize(blocks, grey, cv::Size(320, 240), 0, 0, cv::INTER_NEAREST);
  cv::GaussianBlur(grey, grey, cv::Size(3, 3), 0.8);
  cv::cvtColor(grey, rgb, cv::COLOR_GRAY2BGR);
  return rgb;
}

// Depth in 8-pixel blocks of 1-2 m (edges everywhere: a misplaced pixel shows).
inline cv::Mat blockDepth(int seed = 5) {
  cv::Mat blocks(240 / 8, 320 / 8, CV_32FC1);
  cv::RNG rng(seed);
  rng.fill(blocks, cv::RNG::UNIFORM, 1.0f, 2.0f);
  cv::Mat depth;
  cv::resize(blocks, depth, cv::Size(320, 240), 0, 0, cv::INTER_NEAREST);
  return depth;
}

inline cv::Mat rampDepth() {
  cv::Mat depth(240, 320, CV_32FC1);
  for (int u = 0; u < 320; ++u) depth.col(u).setTo(1.0f + static_cast<float>(u) / 320.0f);
  return depth;
}

}  // namespace rtabmap::test

#pragma once
// Several cameras in one frame are side by side in its images, one equal share of the columns
// each (SensorData). What is done to them is done to each camera's columns on its own, so that
// nothing crosses a camera boundary. Private to the geometry area.
#include <opencv2/core.hpp>

#include <vector>

namespace rtabmap::geometry_detail {

// f(sub-image of camera i, i) for each of the n cameras, joined side by side again (an empty
// image stays empty).
template <class F>
cv::Mat eachCamera(const cv::Mat& image, int n, F f) {
  if (image.empty() || n <= 0) return image;
  const int w = image.cols / n;
  std::vector<cv::Mat> parts;
  for (int i = 0; i < n; ++i) parts.push_back(f(image.colRange(i * w, (i + 1) * w), i));
  if (parts.size() == 1) return parts.front();
  cv::Mat out;
  cv::hconcat(parts, out);
  return out;
}

}  // namespace rtabmap::geometry_detail

#pragma once
// Pyramidal Lucas-Kanade restricted to the row, for rectified stereo pairs (internal to the
// features area). Rectified views of a point share a row, so the only unknown is the disparity:
// a 1D Gauss-Newton on the horizontal shift, coarse to fine. OpenCV's 2D tracker also estimates a
// vertical shift, which a window a few pixels high cannot constrain: on real images (EuRoC) it
// drifts off the row for most features. This is the tracker RTAB-Map uses for stereo.
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include <vector>

namespace rtabmap::features_detail {

struct RowFlowOptions {
  int winWidth = 15, winHeight = 3;  // odd sizes work best: the window is centred on the point
  int iterations = 30;               // per pyramid level
  int maxLevel = 5;                  // levels above the image; those the window does not fit are skipped
  double eps = 0.01;                 // pixels: a level ends when the update is smaller
  float minCorrelation = 0.8f;       // ZNCC of the two windows at the match, else rejected
};

// Disparity (left x - right x) of each left point; 0 where the window leaves the image, has no
// horizontal texture, or does not match (correlation under minCorrelation). Both images 8-bit
// grey of the same size.
std::vector<float> rowFlowDisparities(const cv::Mat& leftGrey, const cv::Mat& rightGrey,
                                      const std::vector<cv::Point2f>& leftPoints, const RowFlowOptions& options);

}  // namespace rtabmap::features_detail

#include "RowFlow.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace rtabmap::features_detail {
namespace {

// Bilinear sample of a CV_32F image; the caller keeps (x, y) inside [0, cols-1) x [0, rows-1).
float sample(const cv::Mat& m, float x, float y) {
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float ax = x - x0, ay = y - y0;
  const float* r0 = m.ptr<float>(y0) + x0;
  const float* r1 = m.ptr<float>(y0 + 1) + x0;
  return (1 - ay) * ((1 - ax) * r0[0] + ax * r0[1]) + ay * ((1 - ax) * r1[0] + ax * r1[1]);
}

bool windowInside(const cv::Mat& m, float x, float y, int hw, int hh) {
  return x - hw >= 0.0f && y - hh >= 0.0f && x + hw < m.cols - 1 && y + hh < m.rows - 1;
}

// Zero-mean normalised cross-correlation of two equally long sample lists.
float zncc(const std::vector<float>& a, const std::vector<float>& b) {
  const size_t n = a.size();
  double ma = 0, mb = 0;
  for (size_t i = 0; i < n; ++i) ma += a[i], mb += b[i];
  ma /= n;
  mb /= n;
  double ab = 0, aa = 0, bb = 0;
  for (size_t i = 0; i < n; ++i) {
    const double da = a[i] - ma, db = b[i] - mb;
    ab += da * db, aa += da * da, bb += db * db;
  }
  return aa > 0 && bb > 0 ? static_cast<float>(ab / std::sqrt(aa * bb)) : 0.0f;
}

struct Pyramids {
  std::vector<cv::Mat> left, right, gradX;  // CV_32F, level 0 = full resolution
};

Pyramids buildPyramids(const cv::Mat& leftGrey, const cv::Mat& rightGrey, int maxLevel) {
  Pyramids p;
  cv::Mat l, r;
  leftGrey.convertTo(l, CV_32F);
  rightGrey.convertTo(r, CV_32F);
  cv::buildPyramid(l, p.left, maxLevel);
  cv::buildPyramid(r, p.right, maxLevel);
  p.gradX.resize(p.left.size());
  // Scharr's x-derivative, normalised to grey levels per pixel (its kernel weights sum to 32).
  for (size_t i = 0; i < p.left.size(); ++i) cv::Scharr(p.left[i], p.gradX[i], CV_32F, 1, 0, 1.0 / 32.0);
  return p;
}

}  // namespace

std::vector<float> rowFlowDisparities(const cv::Mat& leftGrey, const cv::Mat& rightGrey,
                                      const std::vector<cv::Point2f>& leftPoints, const RowFlowOptions& o) {
  std::vector<float> out(leftPoints.size(), 0.0f);
  if (leftPoints.empty()) return out;
  const Pyramids p = buildPyramids(leftGrey, rightGrey, o.maxLevel);
  const int hw = o.winWidth / 2, hh = o.winHeight / 2;
  const size_t n = static_cast<size_t>((2 * hw + 1) * (2 * hh + 1));
  // A window whose mean squared horizontal gradient is under one grey level per pixel has no
  // texture to lock onto along the row (a flat or purely horizontal-edged patch). Coarse levels
  // are blurred: there only a flat window is skipped, else the fine levels would start too far
  // from large disparities to converge.
  const double minHessian = static_cast<double>(n), minCoarseHessian = 1e-3 * static_cast<double>(n);
  std::vector<float> templ(n), grad(n), warped(n);
  for (size_t i = 0; i < leftPoints.size(); ++i) {
    float d = 0.0f;  // disparity at the current level, in that level's pixels
    bool failed = false;
    for (int level = static_cast<int>(p.left.size()) - 1; level >= 0 && !failed; --level) {
      const cv::Mat& L = p.left[static_cast<size_t>(level)];
      const cv::Mat& R = p.right[static_cast<size_t>(level)];
      const cv::Mat& G = p.gradX[static_cast<size_t>(level)];
      const float scale = 1.0f / static_cast<float>(1 << level);
      const bool finest = level == 0;
      float x = leftPoints[i].x * scale, y = leftPoints[i].y * scale;
      if (!finest) {
        // Near the border, a coarse level's window is moved inside the image: its neighbourhood
        // has about the same disparity, and skipping the level would leave the finer ones
        // starting too far from it to converge.
        x = std::clamp(x, static_cast<float>(hw), static_cast<float>(L.cols - 2 - hw));
        y = std::clamp(y, static_cast<float>(hh), static_cast<float>(L.rows - 2 - hh));
      }
      if (!windowInside(L, x, y, hw, hh)) {
        failed = finest;  // coarse levels smaller than the window are skipped
        d *= 2.0f;
        continue;
      }
      double H = 0.0;
      size_t k = 0;
      for (int v = -hh; v <= hh; ++v) {
        for (int u = -hw; u <= hw; ++u, ++k) {
          templ[k] = sample(L, x + u, y + v);
          grad[k] = sample(G, x + u, y + v);
          H += double(grad[k]) * grad[k];
        }
      }
      if (H < (finest ? minHessian : minCoarseHessian)) {
        failed = finest;
        d *= 2.0f;
        continue;
      }
      for (int it = 0; it < o.iterations; ++it) {
        const float xr = x - d;
        if (!windowInside(R, xr, y, hw, hh)) {
          failed = finest;  // a coarse level keeps its estimate: the finer ones may still fit
          break;
        }
        // Gauss-Newton on the shift: R(xr + s) ~ R(xr) + s * dL/dx, so the disparity grows by
        // sum(grad * (R - L)) / sum(grad^2).
        double b = 0.0;
        k = 0;
        for (int v = -hh; v <= hh; ++v) {
          for (int u = -hw; u <= hw; ++u, ++k) b += double(grad[k]) * (sample(R, xr + u, y + v) - templ[k]);
        }
        const float step = static_cast<float>(b / H);
        d += step;
        if (std::fabs(step) < o.eps) break;
      }
      if (!finest) d *= 2.0f;
    }
    if (failed) continue;
    const float xr = leftPoints[i].x - d, y = leftPoints[i].y;
    if (!windowInside(p.right[0], xr, y, hw, hh)) continue;
    size_t k = 0;
    for (int v = -hh; v <= hh; ++v) {
      for (int u = -hw; u <= hw; ++u, ++k) {
        templ[k] = sample(p.left[0], leftPoints[i].x + u, y + v);
        warped[k] = sample(p.right[0], xr + u, y + v);
      }
    }
    if (zncc(templ, warped) >= o.minCorrelation) out[i] = d;
  }
  return out;
}

}  // namespace rtabmap::features_detail

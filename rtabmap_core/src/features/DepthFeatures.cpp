#include "rtabmap_core/features/DepthFeatures.h"

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/SensorData.h"

namespace rtabmap {
namespace {

// Relative depth difference above which two neighbouring depth pixels are taken to lie on
// different surfaces. Kinect-class sensors quantise depth to about 1% at 4 m, and a surface
// seen at a grazing angle changes by a few % per pixel; an object's silhouette against its
// background usually changes by far more than 5%.
constexpr float kDiscontinuityRatio = 0.05f;

inline bool inRange(float d, float minDepth, float maxDepth) {
  return d > 0.0f && (minDepth <= 0.0f || d >= minDepth) && (maxDepth <= 0.0f || d <= maxDepth);
}

template <typename T, typename ToMetres>
int fillDepthMask(const cv::Mat& depth, cv::Mat& small, float minDepth, float maxDepth, ToMetres toMetres) {
  int valid = 0;
  for (int v = 0; v < depth.rows; ++v) {
    const T* in = depth.ptr<T>(v);
    unsigned char* out = small.ptr<unsigned char>(v);
    for (int u = 0; u < depth.cols; ++u) {
      const float d = toMetres(in[u]);
      if (inRange(d, minDepth, maxDepth)) {
        out[u] = 255;
        ++valid;
      }
    }
  }
  return valid;
}

}  // namespace

int depthDecimationFactor(const cv::Size& imageSize, const cv::Size& depthSize) {
  if (imageSize.width <= 0 || imageSize.height <= 0 || depthSize.width <= 0 || depthSize.height <= 0) {
    return 0;
  }
  if (imageSize.width % depthSize.width != 0 || imageSize.height % depthSize.height != 0) return 0;
  const int fx = imageSize.width / depthSize.width;
  const int fy = imageSize.height / depthSize.height;
  return fx == fy ? fx : 0;
}

cv::Mat depthMask(const cv::Mat& depth, const cv::Size& imageSize, float minDepth, float maxDepth,
                  int* validPixels) {
  const int factor = depthDecimationFactor(imageSize, depth.size());
  if (factor == 0) {
    throw std::invalid_argument("depthMask: depth " + std::to_string(depth.cols) + "x" +
                                std::to_string(depth.rows) + " is not a whole fraction of the image " +
                                std::to_string(imageSize.width) + "x" + std::to_string(imageSize.height));
  }
  cv::Mat small = cv::Mat::zeros(depth.size(), CV_8UC1);
  int valid = 0;
  if (depth.type() == CV_16UC1) {
    valid = fillDepthMask<unsigned short>(depth, small, minDepth, maxDepth, [](unsigned short mm) {
      return (mm == 0 || mm == 65535) ? 0.0f : static_cast<float>(mm) * 0.001f;
    });
  } else if (depth.type() == CV_32FC1) {
    valid = fillDepthMask<float>(depth, small, minDepth, maxDepth,
                                 [](float m) { return std::isfinite(m) ? m : 0.0f; });
  } else {
    throw std::invalid_argument("depthMask: depth must be CV_16UC1 or CV_32FC1, got type " +
                                std::to_string(depth.type()));
  }
  if (validPixels) *validPixels = valid;
  if (factor == 1) return small;
  cv::Mat mask;
  cv::resize(small, mask, imageSize, 0, 0, cv::INTER_NEAREST);
  return mask;
}

float keypointDepth(const cv::Mat& depth, const cv::Point2f& imagePoint, int decimation) {
  if (decimation <= 0) return 0.0f;
  const int u = static_cast<int>(std::floor(imagePoint.x + 0.5f)) / decimation;
  const int v = static_cast<int>(std::floor(imagePoint.y + 0.5f)) / decimation;
  const float d = SensorData::depthAt(depth, u, v);
  if (d <= 0.0f) return 0.0f;
  for (int dv = -1; dv <= 1; ++dv) {
    for (int du = -1; du <= 1; ++du) {
      const float n = SensorData::depthAt(depth, u + du, v + dv);
      if (n > 0.0f && std::fabs(n - d) > kDiscontinuityRatio * d) return 0.0f;
    }
  }
  return d;
}

std::vector<cv::Point3f> keypoints3DFromDepth(const std::vector<cv::KeyPoint>& keypoints,
                                              const cv::Mat& depth, const cv::Size& imageSize,
                                              const CameraModel& model, float minDepth, float maxDepth) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<cv::Point3f> points(keypoints.size(), cv::Point3f(nan, nan, nan));
  const int factor = depthDecimationFactor(imageSize, depth.size());
  if (factor == 0 || !model.isValidForProjection()) return points;
  const Eigen::Isometry3d& local = model.localTransform().toEigen();
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const float d = keypointDepth(depth, keypoints[i].pt, factor);
    if (!inRange(d, minDepth, maxDepth)) continue;
    double x, y, z;
    if (!model.project(keypoints[i].pt.x, keypoints[i].pt.y, d, x, y, z)) continue;
    const Eigen::Vector3d p = local * Eigen::Vector3d(x, y, z);
    points[i] = cv::Point3f(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  }
  return points;
}

}  // namespace rtabmap

#include "rtabmap_core/geometry/ImageRectification.h"

#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/features/DepthFeatures.h"

namespace rtabmap {
namespace {

// Column range of camera i of n side by side.
cv::Mat part(const cv::Mat& image, int i, int n) {
  const int w = image.cols / n;
  return image.colRange(i * w, (i + 1) * w);
}

cv::Mat joined(const std::vector<cv::Mat>& parts) {
  if (parts.size() == 1) return parts.front();
  cv::Mat out;
  cv::hconcat(parts, out);
  return out;
}

// The depth of camera `m` (registered to its raw colour image, `factor` times smaller).
cv::Mat rectifyDepthOf(const CameraModel& m, const cv::Mat& depth, int factor) {
  return factor == 1 ? m.rectifyDepth(depth) : m.scaled(1.0 / factor).rectifyDepth(depth);
}

SensorData rectifyRgbd(const SensorData& data) {
  const std::vector<CameraModel>& models = data.cameraModels();
  const int n = static_cast<int>(models.size());
  const cv::Mat& image = data.imageRaw();
  const cv::Mat& depth = data.depthOrRightRaw();
  int factor = 0;
  if (!depth.empty()) {
    factor = depthDecimationFactor(image.size(), depth.size());
    if (factor == 0) {
      throw FormatError("cannot rectify: depth " + std::to_string(depth.cols) + "x" + std::to_string(depth.rows) +
                        " is not a whole fraction of the image " + std::to_string(image.cols) + "x" +
                        std::to_string(image.rows));
    }
  }
  std::vector<cv::Mat> images, depths;
  std::vector<CameraModel> rectified;
  for (int i = 0; i < n; ++i) {
    const CameraModel& m = models[static_cast<size_t>(i)];
    images.push_back(m.rectifyImage(part(image, i, n)));
    if (!depth.empty()) depths.push_back(rectifyDepthOf(m, part(depth, i, n), factor));
    rectified.push_back(m.rectified());
  }
  SensorData out = data;
  out.setRGBDImage(joined(images), depth.empty() ? depth : joined(depths), rectified);
  return out;
}

SensorData rectifyStereo(const SensorData& data) {
  const std::vector<StereoCameraModel>& models = data.stereoCameraModels();
  const int n = static_cast<int>(models.size());
  std::vector<cv::Mat> lefts, rights;
  std::vector<StereoCameraModel> rectified;
  for (int i = 0; i < n; ++i) {
    const StereoCameraModel& m = models[static_cast<size_t>(i)];
    cv::Mat left, right;
    m.rectify(part(data.imageRaw(), i, n), part(data.depthOrRightRaw(), i, n), left, right);
    lefts.push_back(left);
    rights.push_back(right);
    rectified.push_back(m.rectified());
  }
  SensorData out = data;
  out.setStereoImage(joined(lefts), joined(rights), rectified);
  return out;
}

}  // namespace

bool needsRectification(const SensorData& data) {
  for (const CameraModel& m : data.cameraModels()) {
    if (!m.isRectified()) return true;
  }
  for (const StereoCameraModel& m : data.stereoCameraModels()) {
    if (!m.left().isRectified() || !m.right().isRectified()) return true;
  }
  return false;
}

SensorData rectifyImages(const SensorData& data) {
  if (!needsRectification(data)) return data;
  SensorData raw = data;
  if (raw.imageRaw().empty() || raw.depthOrRightRaw().empty()) raw.uncompress(true, true, false, false);
  if (raw.imageRaw().empty()) return data;  // no image: nothing to rectify
  return raw.isStereo() ? rectifyStereo(raw) : rectifyRgbd(raw);
}

}  // namespace rtabmap

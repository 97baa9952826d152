#include "rtabmap_core/geometry/ImageRectification.h"

#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "SideBySide.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/features/DepthFeatures.h"

namespace rtabmap {
namespace {

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
  std::vector<CameraModel> rectified;
  for (const CameraModel& m : models) rectified.push_back(m.rectified());
  const cv::Mat images =
      geometry_detail::eachCamera(image, n, [&](const cv::Mat& part, int i) { return models[size_t(i)].rectifyImage(part); });
  const cv::Mat depths = depth.empty() ? depth : geometry_detail::eachCamera(depth, n, [&](const cv::Mat& part, int i) {
    return rectifyDepthOf(models[size_t(i)], part, factor);
  });
  SensorData out = data;
  out.setRGBDImage(images, depths, rectified);
  return out;
}

SensorData rectifyStereo(const SensorData& data) {
  const std::vector<StereoCameraModel>& models = data.stereoCameraModels();
  const int n = static_cast<int>(models.size());
  std::vector<StereoCameraModel> rectified;
  for (const StereoCameraModel& m : models) rectified.push_back(m.rectified());
  const cv::Mat lefts = geometry_detail::eachCamera(
      data.imageRaw(), n, [&](const cv::Mat& part, int i) { return models[size_t(i)].left().rectifyImage(part); });
  const cv::Mat rights = geometry_detail::eachCamera(
      data.depthOrRightRaw(), n, [&](const cv::Mat& part, int i) { return models[size_t(i)].right().rectifyImage(part); });
  SensorData out = data;
  out.setStereoImage(lefts, rights, rectified);
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

#include "rtabmap_core/geometry/ImageDecimation.h"

#include <opencv2/imgproc.hpp>

#include "SideBySide.h"
#include "rtabmap_core/features/DepthFeatures.h"

namespace rtabmap {
namespace {

// Each of the n side-by-side sub-images shrunk by area averaging on its own: shrinking the whole
// image would average pixels across a camera boundary and, when a camera's width is not a
// multiple of the decimation, move the boundaries off the columns the models expect.
cv::Mat shrinkSideBySide(const cv::Mat& image, int n, int decimation) {
  const cv::Size size(image.cols / n / decimation, image.rows / decimation);
  return geometry_detail::eachCamera(image, n, [&](const cv::Mat& part, int) {
    cv::Mat small;
    cv::resize(part, small, size, 0, 0, cv::INTER_AREA);
    return small;
  });
}

}  // namespace

SensorData decimateImages(const SensorData& data, int decimation) {
  const cv::Mat& image = data.imageRaw();
  if (decimation <= 1 || image.empty()) return data;
  SensorData out = data;
  if (data.isStereo()) {
    // Every camera's model: the cameras stay side by side, each shrunk by the same factor.
    const int n = static_cast<int>(data.stereoCameraModels().size());
    std::vector<StereoCameraModel> models;
    for (const StereoCameraModel& m : data.stereoCameraModels()) models.push_back(m.scaled(1.0 / decimation));
    out.setStereoImage(shrinkSideBySide(image, n, decimation),
                       shrinkSideBySide(data.depthOrRightRaw(), n, decimation), models);
    return out;
  }
  const cv::Size size(image.cols / decimation, image.rows / decimation);
  cv::Mat small;
  cv::resize(image, small, size, 0, 0, cv::INTER_AREA);
  std::vector<CameraModel> models;
  for (const CameraModel& m : data.cameraModels()) models.push_back(m.scaled(1.0 / decimation));
  cv::Mat depth = data.depthOrRightRaw();
  if (!depth.empty() && depth.cols > size.width && depthDecimationFactor(image.size(), depth.size()) > 0) {
    cv::Mat d;
    cv::resize(depth, d, size, 0, 0, cv::INTER_NEAREST);
    depth = d;
  }
  out.setRGBDImage(small, depth, models);
  return out;
}

void scaleKeypoints(std::vector<cv::KeyPoint>& keypoints, float scale) {
  if (scale == 1.f) return;
  for (cv::KeyPoint& k : keypoints) {
    k.pt *= scale;
    k.size *= scale;
  }
}

}  // namespace rtabmap

#include <opencv2/imgproc.hpp>

#include "rtabmap_core/features/DepthFeatures.h"
#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/registration/RegistrationVis.h"

namespace rtabmap {
namespace {

cv::Mat greyOf(const cv::Mat& image) {
  if (image.empty() || image.depth() != CV_8U) return cv::Mat();
  if (image.channels() == 1) return image;
  cv::Mat grey;
  if (image.channels() == 3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  if (image.channels() == 4) cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  return grey;
}

}  // namespace

VisualFrame VisualFrame::fromSensorData(const SensorData& data, const ImageFeatures& features,
                                        const StereoOptions& stereoOptions) {
  VisualFrame f;
  f.keypoints = features.keypoints;
  f.points3D = features.points3D;
  f.descriptors = features.descriptors;
  f.grey = greyOf(data.imageRaw());
  if (data.isStereo()) {
    const StereoCameraModel stereo = data.stereoCameraModels().front();
    f.model = stereo.left();
    f.stereoBaseline = stereo.baseline();
    const cv::Mat right = greyOf(data.depthOrRightRaw());
    const cv::Mat left = f.grey;
    if (!left.empty() && !right.empty() && left.size() == right.size()) {
      f.points3DAt = [left, right, stereo, stereoOptions](const std::vector<cv::KeyPoint>& kps) {
        std::vector<cv::Point2f> pts;
        cv::KeyPoint::convert(kps, pts);
        return keypoints3DFromDisparities(kps, computeStereoDisparities(left, right, pts, stereoOptions), stereo);
      };
    }
  } else if (data.cameraModels().size() == 1) {
    f.model = data.cameraModels().front();
    const cv::Mat depth = data.depthOrRightRaw();
    const cv::Size imageSize = data.imageRaw().size();
    const CameraModel model = f.model;
    if (!depth.empty() && (depth.type() == CV_16UC1 || depth.type() == CV_32FC1) &&
        depthDecimationFactor(imageSize, depth.size()) > 0) {
      f.points3DAt = [depth, imageSize, model](const std::vector<cv::KeyPoint>& kps) {
        return keypoints3DFromDepth(kps, depth, imageSize, model);
      };
    }
  }
  // Models built from fx, fy, cx, cy alone may not know the image size; take it from the image.
  if (f.model.imageWidth() == 0 && !data.imageRaw().empty()) f.model.setImageSize(data.imageRaw().size());
  return f;
}

}  // namespace rtabmap

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

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

// Several cameras side by side: every model (image size = its sub-image), and 3D of arbitrary
// image points through the depth sub-image and model of the camera under each point.
void severalCamerasOf(const SensorData& data, VisualFrame& f) {
  const int n = static_cast<int>(data.cameraModels().size());
  const cv::Size imageSize = data.imageRaw().size();
  const cv::Size cameraSize(imageSize.width / n, imageSize.height);
  f.models = data.cameraModels();
  for (CameraModel& m : f.models) {
    if (m.imageWidth() == 0 && cameraSize.width > 0) m.setImageSize(cameraSize);
  }
  f.model = f.models.front();
  const cv::Mat depth = data.depthOrRightRaw();
  if (depth.empty() || (depth.type() != CV_16UC1 && depth.type() != CV_32FC1) || imageSize.width % n != 0 ||
      depth.cols % n != 0 || depthDecimationFactor(cameraSize, cv::Size(depth.cols / n, depth.rows)) == 0) {
    return;
  }
  const std::vector<CameraModel> models = f.models;
  f.points3DAt = [depth, cameraSize, models](const std::vector<cv::KeyPoint>& kps) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<cv::Point3f> out(kps.size(), cv::Point3f(nan, nan, nan));
    const int n = static_cast<int>(models.size());
    const int dw = depth.cols / n;
    for (int c = 0; c < n; ++c) {
      std::vector<cv::KeyPoint> local;
      std::vector<size_t> index;
      for (size_t k = 0; k < kps.size(); ++k) {
        const int camera = static_cast<int>(std::floor(kps[k].pt.x / static_cast<float>(cameraSize.width)));
        if (camera != c) continue;
        local.push_back(kps[k]);
        local.back().pt.x -= static_cast<float>(c * cameraSize.width);
        index.push_back(k);
      }
      if (local.empty()) continue;
      const std::vector<cv::Point3f> p =
          keypoints3DFromDepth(local, depth.colRange(c * dw, (c + 1) * dw), cameraSize, models[static_cast<size_t>(c)]);
      for (size_t j = 0; j < index.size(); ++j) out[index[j]] = p[j];
    }
    return out;
  };
}

// Several stereo cameras side by side (left images, and right images the same way): every
// left model (image size = its sub-image), and 3D of arbitrary image points by disparity in the
// left and right sub-images of the camera under each point, through that camera's model.
void severalStereoCamerasOf(const SensorData& data, VisualFrame& f, const StereoOptions& stereoOptions) {
  const std::vector<StereoCameraModel> stereo = data.stereoCameraModels();
  const int n = static_cast<int>(stereo.size());
  const cv::Size imageSize = data.imageRaw().size();
  const cv::Size cameraSize(imageSize.width / n, imageSize.height);
  f.models.clear();
  for (const StereoCameraModel& s : stereo) {
    CameraModel m = s.left();
    if (m.imageWidth() == 0 && cameraSize.width > 0) m.setImageSize(cameraSize);
    f.models.push_back(m);
  }
  f.model = f.models.front();
  f.stereoBaseline = stereo.front().baseline();
  const cv::Mat right = greyOf(data.depthOrRightRaw());
  const cv::Mat left = f.grey;
  if (left.empty() || right.empty() || left.size() != right.size() || imageSize.width % n != 0) return;
  const int w = cameraSize.width;
  f.points3DAt = [left, right, stereo, stereoOptions, w](const std::vector<cv::KeyPoint>& kps) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<cv::Point3f> out(kps.size(), cv::Point3f(nan, nan, nan));
    for (int c = 0; c < static_cast<int>(stereo.size()); ++c) {
      std::vector<cv::KeyPoint> local;
      std::vector<size_t> index;
      for (size_t k = 0; k < kps.size(); ++k) {
        if (static_cast<int>(std::floor(kps[k].pt.x / static_cast<float>(w))) != c) continue;
        local.push_back(kps[k]);
        local.back().pt.x -= static_cast<float>(c * w);
        index.push_back(k);
      }
      if (local.empty()) continue;
      // Copies: optical flow reads around a view's ROI, i.e. the neighbouring camera's pixels.
      const cv::Mat l = left.colRange(c * w, (c + 1) * w).clone();
      const cv::Mat r = right.colRange(c * w, (c + 1) * w).clone();
      std::vector<cv::Point2f> pts;
      cv::KeyPoint::convert(local, pts);
      const std::vector<cv::Point3f> p = keypoints3DFromDisparities(
          local, computeStereoDisparities(l, r, pts, stereoOptions), stereo[static_cast<size_t>(c)]);
      for (size_t j = 0; j < index.size(); ++j) out[index[j]] = p[j];
    }
    return out;
  };
}

}  // namespace

int VisualFrame::cameraWidth() const {
  if (models.empty()) return model.imageWidth() > 0 ? model.imageWidth() : grey.cols;
  if (models.front().imageWidth() > 0) return models.front().imageWidth();
  return grey.cols / static_cast<int>(models.size());
}

int VisualFrame::cameraOf(float x) const {
  const int w = cameraWidth();
  if (models.size() <= 1 || w <= 0) return 0;
  const int c = static_cast<int>(std::floor(x / static_cast<float>(w)));
  return std::min(std::max(c, 0), static_cast<int>(models.size()) - 1);
}

VisualFrame VisualFrame::fromSensorData(const SensorData& data, const ImageFeatures& features,
                                        const StereoOptions& stereoOptions) {
  VisualFrame f;
  f.keypoints = features.keypoints;
  f.points3D = features.points3D;
  f.descriptors = features.descriptors;
  f.grey = greyOf(data.imageRaw());
  if (data.stereoCameraModels().size() > 1) {
    severalStereoCamerasOf(data, f, stereoOptions);
  } else if (data.isStereo()) {
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
  } else if (data.cameraModels().size() > 1) {
    severalCamerasOf(data, f);
  }
  // Models built from fx, fy, cx, cy alone may not know the image size; take it from the image.
  if (f.model.imageWidth() == 0 && !data.imageRaw().empty()) f.model.setImageSize(data.imageRaw().size());
  if (f.models.empty() && !data.isStereo() && !data.cameraModels().empty()) f.models.push_back(f.model);
  return f;
}

}  // namespace rtabmap

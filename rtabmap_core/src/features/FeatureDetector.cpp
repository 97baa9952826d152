// The feature pipeline shared by odometry / registration (Vis/) and the vocabulary (Kp/).
#include "rtabmap_core/features/FeatureDetector.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

#include "OpenCvFeatures.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/features/DepthFeatures.h"
#include "rtabmap_core/geometry/SensorData.h"

namespace rtabmap {

struct FeatureDetector::Impl {
  explicit Impl(const FeatureOptions& o) : opencv(o.type, o.detectorParameters) {}
  features_detail::OpenCvFeatures opencv;
};

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// 8-bit grey view of an 8-bit grey, BGR or BGRA image; empty for anything else.
cv::Mat toGrey(const cv::Mat& image) {
  if (image.depth() != CV_8U) return cv::Mat();
  if (image.channels() == 1) return image;
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  }
  return grey;
}

std::string sizeText(const cv::Size& s) {
  return std::to_string(s.width) + "x" + std::to_string(s.height);
}

cv::Rect roiOf(const cv::Size& size, const std::array<double, 4>& r) {
  const int left = static_cast<int>(std::floor(r[0] * size.width));
  const int right = static_cast<int>(std::floor(r[1] * size.width));
  const int top = static_cast<int>(std::floor(r[2] * size.height));
  const int bottom = static_cast<int>(std::floor(r[3] * size.height));
  return cv::Rect(left, top, std::max(0, size.width - left - right), std::max(0, size.height - top - bottom));
}

bool isFinitePoint(const cv::Point3f& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// Removes keypoints (and their 3D points and descriptor rows) for which keep(i) is false.
template <typename Keep>
void filterFeatures(ImageFeatures& f, Keep keep) {
  std::vector<cv::KeyPoint> k;
  std::vector<cv::Point3f> p;
  std::vector<int> rows;
  for (size_t i = 0; i < f.keypoints.size(); ++i) {
    if (!keep(i)) continue;
    k.push_back(f.keypoints[i]);
    if (!f.points3D.empty()) p.push_back(f.points3D[i]);
    rows.push_back(static_cast<int>(i));
  }
  if (k.size() == f.keypoints.size()) return;
  cv::Mat d;
  if (!f.descriptors.empty()) {
    d.create(static_cast<int>(rows.size()), f.descriptors.cols, f.descriptors.type());
    for (size_t i = 0; i < rows.size(); ++i) f.descriptors.row(rows[i]).copyTo(d.row(static_cast<int>(i)));
  }
  f.keypoints = std::move(k);
  f.points3D = std::move(p);
  f.descriptors = d;
}

// Camera i's columns [i*w, (i+1)*w) of side-by-side images. A copy, not a view: detectors,
// descriptors and optical flow read pixels around the ROI of a view, which here would be the
// neighbouring camera's.
cv::Mat cameraColumns(const cv::Mat& image, int i, int w) { return image.colRange(i * w, (i + 1) * w).clone(); }

// Each of n cameras keeps max / N keypoints (at least 1 each); 0 stays "no limit".
int featuresPerCamera(int maxFeatures, int n) { return maxFeatures > 0 ? std::max(1, maxFeatures / n) : 0; }

// Features of n side-by-side cameras of width w, camera i's from oneCamera(i, &why) in its own
// sub-image coordinates: keypoints offset into the combined image, 3D points (already in the
// base frame) and descriptors appended. A camera that fails (why set) costs its own features
// only; the frame fails only when no camera gave any, with the last camera's reason.
ImageFeatures mergeSideBySideCameras(int n, int w, FeatureExtractionInfo& info,
                                     const std::function<ImageFeatures(int, std::string*)>& oneCamera) {
  ImageFeatures all;
  std::vector<cv::Mat> descriptors;
  std::string lastProblem;
  for (int i = 0; i < n; ++i) {
    std::string why;
    ImageFeatures f = oneCamera(i, &why);
    if (!why.empty()) {
      lastProblem = "camera " + std::to_string(i) + ": " + why;
      continue;
    }
    for (cv::KeyPoint& k : f.keypoints) k.pt.x += static_cast<float>(i * w);
    all.keypoints.insert(all.keypoints.end(), f.keypoints.begin(), f.keypoints.end());
    all.points3D.insert(all.points3D.end(), f.points3D.begin(), f.points3D.end());
    if (!f.descriptors.empty()) descriptors.push_back(f.descriptors);
  }
  if (all.keypoints.empty() && !lastProblem.empty()) {
    info.problem = lastProblem;
    return ImageFeatures();
  }
  if (!descriptors.empty()) cv::vconcat(descriptors, all.descriptors);
  info.with3D = all.validPoints3D();
  return all;
}

}  // namespace

FeatureDetector::FeatureDetector(const FeatureOptions& options) : options_(options) {
  std::string why;
  if (!options_.IsValid(&why)) throw ParameterError("feature detector: " + why);
  impl_ = std::make_unique<Impl>(options_);
}

FeatureDetector::~FeatureDetector() = default;

std::unique_ptr<FeatureDetector> FeatureDetector::create(const ParametersMap& parameters, FeatureGroup group) {
  return std::make_unique<FeatureDetector>(FeatureOptions::fromParameters(parameters, group));
}

std::vector<cv::KeyPoint> FeatureDetector::detect(const cv::Mat& image, const cv::Mat& mask) const {
  if (options_.maxFeatures < 0 || image.empty()) return {};
  const cv::Mat grey = toGrey(image);
  if (grey.empty()) throw FormatError("feature detection needs an 8-bit grey, BGR or BGRA image");
  if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != grey.size())) {
    throw FormatError("feature detection mask must be CV_8UC1 of the image size");
  }
  return detectUpTo(grey, mask, options_.maxFeatures);
}

std::vector<cv::KeyPoint> FeatureDetector::detectUpTo(const cv::Mat& grey, const cv::Mat& mask, int maxFeatures) const {
  std::vector<cv::KeyPoint> keypoints;
  const cv::Rect roi = roiOf(grey.size(), options_.roiRatios);
  if (roi.area() <= 0) return keypoints;
  const int cells = options_.gridRows * options_.gridCols;
  // Each cell keeps its share of the strongest: features spread over the image constrain the
  // motion better than the same number bunched on the most textured object.
  const int perCell = maxFeatures > 0 ? std::max(1, maxFeatures / cells) : 0;
  for (int r = 0; r < options_.gridRows; ++r) {
    for (int c = 0; c < options_.gridCols; ++c) {
      const int x0 = roi.x + c * roi.width / options_.gridCols;
      const int x1 = roi.x + (c + 1) * roi.width / options_.gridCols;
      const int y0 = roi.y + r * roi.height / options_.gridRows;
      const int y1 = roi.y + (r + 1) * roi.height / options_.gridRows;
      const cv::Rect cell(x0, y0, x1 - x0, y1 - y0);
      if (cell.area() <= 0) continue;
      cv::Mat cellMask;
      if (!mask.empty()) {
        cellMask = mask(cell);
        if (cv::countNonZero(cellMask) == 0) continue;
      }
      std::vector<cv::KeyPoint> cellKeypoints = impl_->opencv.detect(grey(cell), cellMask, perCell);
      for (cv::KeyPoint& k : cellKeypoints) {
        k.pt.x += static_cast<float>(cell.x);
        k.pt.y += static_cast<float>(cell.y);
        keypoints.push_back(k);
      }
    }
  }
  if (options_.subPixIterations > 0 && !keypoints.empty()) {
    std::vector<cv::Point2f> points;
    cv::KeyPoint::convert(keypoints, points);
    cv::cornerSubPix(grey, points, cv::Size(options_.subPixWinSize, options_.subPixWinSize), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, options_.subPixIterations,
                                      options_.subPixEps));
    for (size_t i = 0; i < keypoints.size(); ++i) keypoints[i].pt = points[i];
  }
  return keypoints;
}

cv::Mat FeatureDetector::compute(const cv::Mat& image, std::vector<cv::KeyPoint>& keypoints) const {
  if (keypoints.empty() || image.empty()) {
    keypoints.clear();
    return cv::Mat();
  }
  const cv::Mat grey = toGrey(image);
  if (grey.empty()) throw FormatError("feature description needs an 8-bit grey, BGR or BGRA image");
  cv::Mat descriptors = impl_->opencv.compute(grey, keypoints);
  if (descriptors.rows != static_cast<int>(keypoints.size())) keypoints.clear();
  return descriptors;
}

ImageFeatures FeatureDetector::extract(const SensorData& data, FeatureExtractionInfo* infoOut) const {
  FeatureExtractionInfo localInfo;
  FeatureExtractionInfo& info = infoOut ? *infoOut : localInfo;
  info = FeatureExtractionInfo();
  ImageFeatures features;
  auto problem = [&](const std::string& text) {
    info.problem = text;
    return ImageFeatures();
  };

  const cv::Mat& image = data.imageRaw();
  if (image.empty()) return problem("no image");
  const cv::Mat grey = toGrey(image);
  if (grey.empty()) {
    return problem("unsupported image type " + std::to_string(image.type()) + " (8-bit grey, BGR or BGRA expected)");
  }
  if (options_.maxFeatures < 0) return features;  // Kp/MaxFeatures < 0: no features wanted

  const cv::Mat& depthOrRight = data.depthOrRightRaw();
  if (data.isStereo()) {
    if (depthOrRight.empty()) return problem("stereo frame without its right image");
    const cv::Mat rightGrey = toGrey(depthOrRight);
    if (rightGrey.empty() || rightGrey.size() != grey.size()) {
      return problem("right image " + sizeText(depthOrRight.size()) + " (type " + std::to_string(depthOrRight.type()) +
                     ") does not match the left image " + sizeText(grey.size()));
    }
    if (data.stereoCameraModels().size() > 1) return extractSeveralStereoCameras(data, grey, rightGrey, info);
    std::string why;
    features = extractStereoCamera(grey, rightGrey, data.stereoCameraModels().front(), options_.maxFeatures, info, &why);
    if (!why.empty()) return problem(why);
    info.with3D = features.validPoints3D();
    return features;
  }
  if (data.cameraModels().size() > 1) return extractSeveralCameras(data, grey, info);
  const CameraModel* model = data.cameraModels().empty() ? nullptr : &data.cameraModels().front();
  std::string why;
  features = extractDepthCamera(grey, depthOrRight, model, options_.maxFeatures, info, &why);
  if (!why.empty()) return problem(why);
  info.with3D = features.validPoints3D();
  return features;
}

ImageFeatures FeatureDetector::extractStereoCamera(const cv::Mat& grey, const cv::Mat& rightGrey,
                                                   const StereoCameraModel& model, int maxFeatures,
                                                   FeatureExtractionInfo& info, std::string* problem) const {
  ImageFeatures features;
  if (!model.isValidForProjection()) {
    *problem = "stereo camera model not valid (fx " + std::to_string(model.left().fx()) + ", baseline " +
               std::to_string(model.baseline()) + ")";
    return features;
  }
  // 3D points by matching each left keypoint along its row of the right image.
  Clock::time_point t0 = Clock::now();
  features.keypoints = detectUpTo(grey, cv::Mat(), maxFeatures);
  info.detected += static_cast<int>(features.keypoints.size());
  info.timeDetectionMs += msSince(t0);

  t0 = Clock::now();
  features.descriptors = compute(grey, features.keypoints);
  info.described += static_cast<int>(features.keypoints.size());
  info.timeDescriptionMs += msSince(t0);

  t0 = Clock::now();
  std::vector<cv::Point2f> left;
  cv::KeyPoint::convert(features.keypoints, left);
  const std::vector<float> disparities = computeStereoDisparities(grey, rightGrey, left, options_.stereo);
  features.points3D = keypoints3DFromDisparities(features.keypoints, disparities, model);
  // Drop keypoints measured outside the depth range; keep those without disparity (their 2D
  // position still constrains a PnP estimate).
  filterFeatures(features, [&](size_t i) {
    if (!isFinitePoint(features.points3D[i])) return true;
    const double depth = model.computeDepth(disparities[i]);
    return (options_.minDepth <= 0.0f || depth >= options_.minDepth) &&
           (options_.maxDepth <= 0.0f || depth <= options_.maxDepth);
  });
  info.time3DMs += msSince(t0);
  return features;
}

ImageFeatures FeatureDetector::extractDepthCamera(const cv::Mat& grey, const cv::Mat& depth, const CameraModel* model,
                                                  int maxFeatures, FeatureExtractionInfo& info,
                                                  std::string* problem) const {
  ImageFeatures features;
  if (model && !model->isValidForProjection()) {
    *problem = "camera model not valid for projection (fx " + std::to_string(model->fx()) + ", fy " +
               std::to_string(model->fy()) + ")";
    return features;
  }
  int decimation = 0;
  cv::Mat mask;
  if (!depth.empty()) {
    if (depth.type() != CV_16UC1 && depth.type() != CV_32FC1) {
      *problem = "unsupported depth type " + std::to_string(depth.type()) + " (CV_16UC1 mm or CV_32FC1 m expected)";
      return features;
    }
    decimation = depthDecimationFactor(grey.size(), depth.size());
    if (decimation == 0) {
      *problem = "depth " + sizeText(depth.size()) + " does not match the image " + sizeText(grey.size()) +
                 " (it must be the same size or smaller by a whole factor)";
      return features;
    }
    if (options_.depthAsMask) {
      int valid = 0;
      mask = depthMask(depth, grey.size(), options_.minDepth, options_.maxDepth, &valid);
      if (valid == 0) {
        *problem = "depth image has no valid pixel in range (all zero, NaN or out of range)";
        return features;
      }
    }
  }

  Clock::time_point t0 = Clock::now();
  features.keypoints = detectUpTo(grey, mask, maxFeatures);
  info.detected += static_cast<int>(features.keypoints.size());
  info.timeDetectionMs += msSince(t0);

  t0 = Clock::now();
  features.descriptors = compute(grey, features.keypoints);
  info.described += static_cast<int>(features.keypoints.size());
  info.timeDescriptionMs += msSince(t0);
  if (decimation == 0 || !model) return features;

  t0 = Clock::now();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  features.points3D.assign(features.keypoints.size(), cv::Point3f(nan, nan, nan));
  std::vector<char> keep(features.keypoints.size(), 1);
  const Eigen::Isometry3d& local = model->localTransform().toEigen();
  for (size_t i = 0; i < features.keypoints.size(); ++i) {
    const float d = keypointDepth(depth, features.keypoints[i].pt, decimation);
    if (d <= 0.0f) continue;
    if ((options_.minDepth > 0.0f && d < options_.minDepth) || (options_.maxDepth > 0.0f && d > options_.maxDepth)) {
      keep[i] = 0;
      continue;
    }
    double x, y, z;
    if (!model->project(features.keypoints[i].pt.x, features.keypoints[i].pt.y, d, x, y, z)) continue;
    const Eigen::Vector3d p = local * Eigen::Vector3d(x, y, z);
    features.points3D[i] = cv::Point3f(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  }
  filterFeatures(features, [&](size_t i) { return keep[i] != 0; });
  info.time3DMs += msSince(t0);
  return features;
}

ImageFeatures FeatureDetector::extractSeveralCameras(const SensorData& data, const cv::Mat& grey,
                                                     FeatureExtractionInfo& info) const {
  const std::vector<CameraModel>& models = data.cameraModels();
  const int n = static_cast<int>(models.size());
  const cv::Mat& depth = data.depthOrRightRaw();
  if (grey.cols % n != 0 || (!depth.empty() && depth.cols % n != 0)) {
    info.problem = "image " + sizeText(grey.size()) + (depth.empty() ? "" : " or depth " + sizeText(depth.size())) +
                   " does not split into " + std::to_string(n) + " side-by-side cameras of equal width";
    return ImageFeatures();
  }
  for (int i = 0; i < n; ++i) {
    const CameraModel& m = models[static_cast<size_t>(i)];
    if (!m.isValidForProjection()) {
      info.problem = "camera " + std::to_string(i) + " model not valid for projection (fx " + std::to_string(m.fx()) +
                     ", fy " + std::to_string(m.fy()) + ")";
      return ImageFeatures();
    }
  }
  const int w = grey.cols / n;
  const int dw = depth.cols / n;
  const int perCamera = featuresPerCamera(options_.maxFeatures, n);
  return mergeSideBySideCameras(n, w, info, [&](int i, std::string* why) {
    const cv::Mat subDepth = depth.empty() ? cv::Mat() : depth.colRange(i * dw, (i + 1) * dw);
    const CameraModel* model = &models[static_cast<size_t>(i)];
    return extractDepthCamera(cameraColumns(grey, i, w), subDepth, model, perCamera, info, why);
  });
}

ImageFeatures FeatureDetector::extractSeveralStereoCameras(const SensorData& data, const cv::Mat& grey,
                                                           const cv::Mat& rightGrey,
                                                           FeatureExtractionInfo& info) const {
  const std::vector<StereoCameraModel>& models = data.stereoCameraModels();
  const int n = static_cast<int>(models.size());
  if (grey.cols % n != 0) {
    info.problem = "stereo images " + sizeText(grey.size()) + " do not split into " + std::to_string(n) +
                   " side-by-side stereo cameras of equal width";
    return ImageFeatures();
  }
  // An invalid model is a calibration error, not a camera facing the void: refuse the frame.
  for (int i = 0; i < n; ++i) {
    const StereoCameraModel& m = models[static_cast<size_t>(i)];
    if (!m.isValidForProjection()) {
      info.problem = "stereo camera " + std::to_string(i) + " model not valid (fx " + std::to_string(m.left().fx()) +
                     ", baseline " + std::to_string(m.baseline()) + ")";
      return ImageFeatures();
    }
  }
  const int w = grey.cols / n;
  const int perCamera = featuresPerCamera(options_.maxFeatures, n);
  return mergeSideBySideCameras(n, w, info, [&](int i, std::string* why) {
    // Each camera's left and right sub-images alone: a disparity search never crosses into the
    // neighbouring camera's columns.
    return extractStereoCamera(cameraColumns(grey, i, w), cameraColumns(rightGrey, i, w),
                               models[static_cast<size_t>(i)], perCamera, info, why);
  });
}

}  // namespace rtabmap

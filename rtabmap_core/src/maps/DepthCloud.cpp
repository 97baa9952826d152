// Stages: depth image / stereo pair / 3D scan -> cloud in the base frame (see LocalGridStages.h).
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <string>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/LocalGridStages.h"

namespace rtabmap {

namespace {

bool inRange(float range, const LocalGridOptions& o) {
  return range >= o.rangeMin && (o.rangeMax <= 0.0f || range <= o.rangeMax);
}

// Colour of depth pixel (u, v) from an RGB image of the same size or an integer multiple.
cv::Vec3b colourAt(const cv::Mat& rgb, int u, int v, int scale) {
  const int x = u * scale, y = v * scale;
  if (rgb.channels() == 1) {
    const uchar g = rgb.at<uchar>(y, x);
    return cv::Vec3b(g, g, g);
  }
  const cv::Vec3b bgr = rgb.at<cv::Vec3b>(y, x);
  return cv::Vec3b(bgr[2], bgr[1], bgr[0]);
}

}  // namespace

Cloud cloudFromDepth(const cv::Mat& depth, const cv::Mat& rgb, const std::vector<CameraModel>& models,
                     const LocalGridOptions& options, DepthCloudStats* statsOut) {
  DepthCloudStats stats;
  Cloud cloud;
  if (depth.empty() || models.empty()) {
    if (statsOut) *statsOut = stats;
    return cloud;
  }
  if (depth.type() != CV_16UC1 && depth.type() != CV_32FC1) {
    throw FormatError("depth image must be CV_16UC1 (mm) or CV_32FC1 (m); got type " +
                      std::to_string(depth.type()));
  }
  const int n = static_cast<int>(models.size());
  if (depth.cols % n != 0) {
    throw FormatError("depth image width " + std::to_string(depth.cols) +
                      " is not a multiple of the number of cameras (" + std::to_string(n) + ")");
  }
  const int subWidth = depth.cols / n;
  int colourScale = 0;
  if (!rgb.empty() && (rgb.type() == CV_8UC3 || rgb.type() == CV_8UC1) && rgb.cols % depth.cols == 0 &&
      rgb.rows % depth.rows == 0 && rgb.cols / depth.cols == rgb.rows / depth.rows) {
    colourScale = rgb.cols / depth.cols;
  }
  const int step = std::max(1, options.depthDecimation);
  const auto& roi = options.depthRoiRatios;
  const int v0 = static_cast<int>(std::floor(roi[2] * depth.rows));
  const int v1 = depth.rows - static_cast<int>(std::floor(roi[3] * depth.rows));
  cloud.reserve(static_cast<size_t>(depth.total() / (step * step)), colourScale > 0);

  for (int cam = 0; cam < n; ++cam) {
    const CameraModel& model = models[cam];
    if (!model.isValidForProjection()) {
      throw FormatError("camera model " + std::to_string(cam) + " cannot project (fx, fy <= 0)");
    }
    const Eigen::Isometry3f opticalToBase = model.localTransform().toEigen().cast<float>();
    // A model calibrated at another resolution than the depth image (e.g. depth registered at
    // half size) is scaled to it.
    const double scale = model.imageWidth() > 0 ? static_cast<double>(subWidth) / model.imageWidth() : 1.0;
    const float fx = static_cast<float>(model.fx() * scale), fy = static_cast<float>(model.fy() * scale);
    const float cx = static_cast<float>(model.cx() * scale), cy = static_cast<float>(model.cy() * scale);
    const int u0 = static_cast<int>(std::floor(roi[0] * subWidth));
    const int u1 = subWidth - static_cast<int>(std::floor(roi[1] * subWidth));
    for (int v = v0; v < v1; v += step) {
      for (int u = u0; u < u1; u += step) {
        ++stats.pixels;
        const int du = cam * subWidth + u;
        const float z = SensorData::depthAt(depth, du, v);
        if (z <= 0.0f) continue;
        ++stats.valid;
        const Eigen::Vector3f optical((static_cast<float>(u) - cx) * z / fx,
                                      (static_cast<float>(v) - cy) * z / fy, z);
        if (!inRange(optical.norm(), options)) {
          ++stats.outOfRange;
          continue;
        }
        const Eigen::Vector3f b = opticalToBase * optical;
        if (colourScale > 0) {
          cloud.push_back(cv::Point3f(b.x(), b.y(), b.z()), colourAt(rgb, du, v, colourScale));
        } else {
          cloud.push_back(cv::Point3f(b.x(), b.y(), b.z()));
        }
      }
    }
  }
  if (statsOut) *statsOut = stats;
  return cloud;
}

cv::Mat depthFromStereo(const cv::Mat& left, const cv::Mat& right, const StereoCameraModel& model,
                        const StereoBMOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw ParameterError("invalid stereo block matching options: " + why);
  if (left.empty() || right.empty()) throw FormatError("stereo pair: an image is empty");
  if (left.size() != right.size()) {
    throw FormatError("stereo pair: left and right images differ in size (" +
                      std::to_string(left.cols) + "x" + std::to_string(left.rows) + " vs " +
                      std::to_string(right.cols) + "x" + std::to_string(right.rows) + ")");
  }
  if (!model.isValidForProjection()) {
    throw FormatError("stereo pair: the camera model cannot project (fx or baseline <= 0)");
  }
  auto grey = [](const cv::Mat& image) {
    cv::Mat g;
    if (image.channels() == 3) cv::cvtColor(image, g, cv::COLOR_BGR2GRAY);
    else if (image.channels() == 4) cv::cvtColor(image, g, cv::COLOR_BGRA2GRAY);
    else g = image;
    if (g.depth() != CV_8U) g.convertTo(g, CV_8U);
    return g;
  };
  cv::Ptr<cv::StereoBM> bm = cv::StereoBM::create(options.numDisparities, options.blockSize);
  bm->setMinDisparity(options.minDisparity);
  bm->setPreFilterSize(options.preFilterSize);
  bm->setPreFilterCap(options.preFilterCap);
  bm->setUniquenessRatio(options.uniquenessRatio);
  bm->setTextureThreshold(options.textureThreshold);
  bm->setSpeckleWindowSize(options.speckleWindowSize);
  bm->setSpeckleRange(options.speckleRange);
  bm->setDisp12MaxDiff(options.disp12MaxDiff);
  cv::Mat disparity;  // CV_16S, 4 fractional bits
  bm->compute(grey(left), grey(right), disparity);

  const float fxB = static_cast<float>(model.left().fx() * model.baseline());
  cv::Mat depth(disparity.size(), CV_32FC1, cv::Scalar(0));
  for (int v = 0; v < disparity.rows; ++v) {
    const short* d = disparity.ptr<short>(v);
    float* z = depth.ptr<float>(v);
    for (int u = 0; u < disparity.cols; ++u) {
      if (d[u] > 0) z[u] = fxB * 16.0f / static_cast<float>(d[u]);
    }
  }
  return depth;
}

cv::Mat depthFromStereoCameras(const cv::Mat& left, const cv::Mat& right, const std::vector<StereoCameraModel>& models,
                               const StereoBMOptions& options) {
  if (models.size() == 1) return depthFromStereo(left, right, models.front(), options);
  const int n = static_cast<int>(models.size());
  if (n == 0) throw FormatError("stereo pair: no camera model");
  if (left.cols % n != 0 || right.cols % n != 0) {
    throw FormatError("stereo images " + std::to_string(left.cols) + " and " + std::to_string(right.cols) +
                      " pixels wide do not split into " + std::to_string(n) + " cameras of equal width");
  }
  const int w = left.cols / n;
  const int rw = right.cols / n;
  std::vector<cv::Mat> depths;
  for (int i = 0; i < n; ++i) {
    // Copies: block matching reads around a view's ROI, i.e. the neighbouring camera's pixels.
    depths.push_back(depthFromStereo(left.colRange(i * w, (i + 1) * w).clone(),
                                     right.colRange(i * rw, (i + 1) * rw).clone(), models[static_cast<size_t>(i)],
                                     options));
  }
  cv::Mat depth;
  cv::hconcat(depths, depth);
  return depth;
}

cv::Mat depthOfFrame(const SensorData& data, const StereoBMOptions& options, std::vector<CameraModel>* models) {
  if (!data.isStereo()) {
    *models = data.cameraModels();
    return data.depthOrRightRaw();
  }
  models->clear();
  for (const StereoCameraModel& stereo : data.stereoCameraModels()) models->push_back(stereo.left());
  return depthFromStereoCameras(data.imageRaw(), data.depthOrRightRaw(), data.stereoCameraModels(), options);
}

Cloud cloudFromScan(const LaserScan& scan, const LocalGridOptions& options, int* invalidOut) {
  Cloud cloud;
  int invalid = 0;
  const Eigen::Isometry3f sensorToBase = scan.localTransform().toEigen().cast<float>();
  const bool colours = scan.hasRGB();
  const int rgbChannel = 3;  // x y z rgb [normals]
  const int step = std::max(1, options.scanDecimation);
  cloud.reserve(static_cast<size_t>(scan.size() / step + 1), colours);
  for (int i = 0; i < scan.size(); i += step) {
    const Eigen::Vector3f p = scan.point(i);
    if (!p.allFinite()) {
      ++invalid;
      continue;
    }
    if (!inRange(p.norm(), options)) continue;
    const Eigen::Vector3f b = sensorToBase * p;
    if (colours) {
      cloud.push_back(cv::Point3f(b.x(), b.y(), b.z()),
                      unpackRgb(scan.data().ptr<float>(0, i)[rgbChannel]));
    } else {
      cloud.push_back(cv::Point3f(b.x(), b.y(), b.z()));
    }
  }
  if (invalidOut) *invalidOut = invalid;
  return cloud;
}

}  // namespace rtabmap

#include "rtabmap_core/geometry/SensorData.h"

#include <opencv2/core.hpp>

#include <cctype>
#include <cmath>
#include <future>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {

namespace {

size_t matBytes(const cv::Mat& m) { return m.empty() ? 0 : m.total() * m.elemSize(); }

bool isJpeg(const std::string& format) {
  std::string f = format;
  for (char& c : f) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return f == ".jpg" || f == ".jpeg" || f == "jpg" || f == "jpeg" || f == ".jpe";
}

// Encodes an image with the requested codec when it can hold it losslessly enough, else png for
// other 8/16-bit layouts, else zlib (compressData): compress() must never refuse an image.
Bytes compressAnyImage(const cv::Mat& image, const std::string& format) {
  if (image.empty()) return {};
  const int depth = image.depth();
  const int cn = image.channels();
  if (depth == CV_8U && (cn == 1 || cn == 3 || (cn == 4 && !isJpeg(format)))) {
    return codec::compressImage(image, format);
  }
  if ((depth == CV_8U || depth == CV_16U) && (cn == 1 || cn == 3 || cn == 4)) {
    return codec::compressImage(image, ".png");
  }
  return codec::compressData(image);
}

}  // namespace

SensorData::SensorData(const cv::Mat& rgb, const cv::Mat& depth, const CameraModel& model, int id,
                       double stamp)
    : id_(id), stamp_(stamp) {
  setRGBDImage(rgb, depth, std::vector<CameraModel>{model});
}

SensorData::SensorData(const cv::Mat& rgb, const cv::Mat& depth,
                       const std::vector<CameraModel>& models, int id, double stamp)
    : id_(id), stamp_(stamp) {
  setRGBDImage(rgb, depth, models);
}

SensorData::SensorData(const cv::Mat& left, const cv::Mat& right, const StereoCameraModel& model,
                       int id, double stamp)
    : id_(id), stamp_(stamp) {
  setStereoImage(left, right, model);
}

SensorData::SensorData(const cv::Mat& left, const cv::Mat& right,
                       const std::vector<StereoCameraModel>& models, int id, double stamp)
    : id_(id), stamp_(stamp) {
  setStereoImage(left, right, models);
}

SensorData::SensorData(const LaserScan& scan, int id, double stamp)
    : id_(id), stamp_(stamp), laserScanRaw_(scan) {}

SensorData::SensorData(const LaserScan& scan, const cv::Mat& rgb, const cv::Mat& depth,
                       const CameraModel& model, int id, double stamp)
    : id_(id), stamp_(stamp), laserScanRaw_(scan) {
  setRGBDImage(rgb, depth, std::vector<CameraModel>{model});
}

void SensorData::setRGBDImage(const cv::Mat& rgb, const cv::Mat& depth,
                              const std::vector<CameraModel>& models) {
  if (!depth.empty() && depth.type() != CV_16UC1 && depth.type() != CV_32FC1) {
    throw FormatError("SensorData: depth must be CV_16UC1 (mm) or CV_32FC1 (m), got type " +
                      std::to_string(depth.type()));
  }
  if (!rgb.empty() && !depth.empty() && !models.empty() && rgb.cols % static_cast<int>(models.size()) != 0) {
    throw FormatError("SensorData: image width " + std::to_string(rgb.cols) +
                      " is not a multiple of the " + std::to_string(models.size()) + " cameras");
  }
  imageRaw_ = rgb;
  depthOrRightRaw_ = depth;
  cameraModels_ = models;
  stereoCameraModels_.clear();
  // New raw data makes the old compressed form stale.
  imageCompressed_.clear();
  depthOrRightCompressed_.clear();
}

void SensorData::setStereoImage(const cv::Mat& left, const cv::Mat& right,
                                const StereoCameraModel& model) {
  setStereoImage(left, right, std::vector<StereoCameraModel>{model});
}

void SensorData::setStereoImage(const cv::Mat& left, const cv::Mat& right,
                                const std::vector<StereoCameraModel>& models) {
  if (!right.empty() && right.type() != CV_8UC1) {
    throw FormatError("SensorData: the right stereo image must be grey (CV_8UC1), got type " +
                      std::to_string(right.type()));
  }
  if (!left.empty() && !right.empty() && left.size() != right.size()) {
    throw FormatError("SensorData: left and right stereo images differ in size");
  }
  // Each camera owns an equal share of the columns of both images (see FeatureDetector).
  const cv::Mat& image = left.empty() ? right : left;
  if (!image.empty() && !models.empty() && image.cols % static_cast<int>(models.size()) != 0) {
    throw FormatError("SensorData: stereo image width " + std::to_string(image.cols) +
                      " is not a multiple of the " + std::to_string(models.size()) + " stereo cameras");
  }
  imageRaw_ = left;
  depthOrRightRaw_ = right;
  stereoCameraModels_ = models;
  cameraModels_.clear();
  imageCompressed_.clear();
  depthOrRightCompressed_.clear();
}

float SensorData::depthAt(const cv::Mat& depth, int u, int v) {
  if (depth.empty() || u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) return 0.0f;
  if (depth.type() == CV_16UC1) {
    const unsigned short mm = depth.at<unsigned short>(v, u);
    // 0 is "no measurement" for every driver; 65535 is the invalid marker of 7-Scenes and
    // some other datasets (no structured-light sensor reports 65.5 m), so both are invalid.
    if (mm == 0 || mm == 65535) return 0.0f;
    return static_cast<float>(mm) * 0.001f;
  }
  if (depth.type() == CV_32FC1) {
    const float m = depth.at<float>(v, u);
    return (std::isfinite(m) && m > 0.0f) ? m : 0.0f;
  }
  throw FormatError("SensorData::depthAt: depth must be CV_16UC1 or CV_32FC1, got type " +
                    std::to_string(depth.type()));
}

void SensorData::setOdom(const Transform& pose, const Eigen::Matrix<double, 6, 6>& covariance) {
  odomPose_ = pose;
  odomCovariance_ = covariance;
}

void SensorData::setFeatures(const std::vector<cv::KeyPoint>& keypoints,
                             const std::vector<cv::Point3f>& keypoints3D, const cv::Mat& descriptors) {
  if (!keypoints3D.empty() && keypoints3D.size() != keypoints.size()) {
    throw FormatError("SensorData::setFeatures: " + std::to_string(keypoints3D.size()) +
                      " 3D points for " + std::to_string(keypoints.size()) + " keypoints");
  }
  if (!descriptors.empty() && descriptors.rows != static_cast<int>(keypoints.size())) {
    throw FormatError("SensorData::setFeatures: " + std::to_string(descriptors.rows) +
                      " descriptors for " + std::to_string(keypoints.size()) + " keypoints");
  }
  keypoints_ = keypoints;
  keypoints3D_ = keypoints3D;
  descriptors_ = descriptors;
}

void SensorData::setCompressed(const Bytes& image, const Bytes& depthOrRight, const Bytes& scan,
                               const Bytes& userData) {
  imageCompressed_ = image;
  depthOrRightCompressed_ = depthOrRight;
  laserScanCompressed_ = scan;
  userDataCompressed_ = userData;
}

SensorData::ScanInfo SensorData::laserScanInfo() const {
  if (laserScanRaw_.empty()) return scanInfo_;
  ScanInfo info;
  info.format = laserScanRaw_.format();
  info.maxPoints = laserScanRaw_.maxPoints();
  info.rangeMin = laserScanRaw_.rangeMin();
  info.rangeMax = laserScanRaw_.rangeMax();
  info.localTransform = laserScanRaw_.localTransform();
  info.angleMin = laserScanRaw_.angleMin();
  info.angleMax = laserScanRaw_.angleMax();
  info.angleIncrement = laserScanRaw_.angleIncrement();
  return info;
}

void SensorData::compress(const std::string& imageFormat) {
  compressImages(imageFormat, false);
  compressScanAndUserData();
}

void SensorData::compressImages(const std::string& imageFormat, bool parallel) {
  auto depthOrRight = [this] {
    if (depthOrRightRaw_.empty()) return;
    if (isStereo()) {
      // The right image stays lossless: jpeg blocks would bias the disparity of every match.
      depthOrRightCompressed_ = compressAnyImage(depthOrRightRaw_, ".png");
    } else {
      depthOrRightCompressed_ = codec::compressDepth(depthOrRightRaw_);
    }
  };
  // The two codecs touch disjoint members; get() rethrows what the other thread threw.
  std::future<void> other;
  if (parallel && !imageRaw_.empty() && !depthOrRightRaw_.empty()) {
    other = std::async(std::launch::async, depthOrRight);
  }
  if (!imageRaw_.empty()) imageCompressed_ = compressAnyImage(imageRaw_, imageFormat);
  if (other.valid()) {
    other.get();
  } else {
    depthOrRight();
  }
}

void SensorData::compressScanAndUserData() {
  if (!laserScanRaw_.empty()) {
    laserScanCompressed_ = codec::compressData(laserScanRaw_.data());
    scanInfo_ = laserScanInfo();
  }
  if (!userDataRaw_.empty()) userDataCompressed_ = codec::compressData(userDataRaw_);
}

void SensorData::uncompress(bool image, bool depthOrRight, bool scan, bool userData) {
  if (image && imageRaw_.empty() && !imageCompressed_.empty()) {
    imageRaw_ = codec::uncompressAny(imageCompressed_);
  }
  if (depthOrRight && depthOrRightRaw_.empty() && !depthOrRightCompressed_.empty()) {
    depthOrRightRaw_ = isStereo() ? codec::uncompressAny(depthOrRightCompressed_)
                                  : codec::uncompressDepth(depthOrRightCompressed_);
  }
  if (scan && laserScanRaw_.empty() && !laserScanCompressed_.empty()) {
    const cv::Mat points = codec::uncompressData(laserScanCompressed_);
    // The LaserScan constructor checks the channel count against the stored format.
    laserScanRaw_ = LaserScan(points, scanInfo_.maxPoints, scanInfo_.rangeMin, scanInfo_.rangeMax,
                              scanInfo_.format, scanInfo_.localTransform);
    if (scanInfo_.angleIncrement != 0.0) {
      laserScanRaw_.setBeamGeometry(scanInfo_.angleMin, scanInfo_.angleMax, scanInfo_.angleIncrement);
    }
  }
  if (userData && userDataRaw_.empty() && !userDataCompressed_.empty()) {
    userDataRaw_ = codec::uncompressData(userDataCompressed_);
  }
}

void SensorData::clearRaw() {
  // Keep the scan's metadata: the compressed scan still needs it to decompress.
  if (!laserScanRaw_.empty()) scanInfo_ = laserScanInfo();
  imageRaw_ = cv::Mat();
  depthOrRightRaw_ = cv::Mat();
  laserScanRaw_ = LaserScan();
  userDataRaw_ = cv::Mat();
}

void SensorData::clearCompressed() {
  imageCompressed_.clear();
  depthOrRightCompressed_.clear();
  laserScanCompressed_.clear();
  userDataCompressed_.clear();
}

size_t SensorData::memoryUsed() const {
  size_t total = sizeof(SensorData);
  total += matBytes(imageRaw_) + matBytes(depthOrRightRaw_) + matBytes(laserScanRaw_.data()) +
           matBytes(userDataRaw_) + matBytes(descriptors_);
  total += matBytes(localGrid_.ground) + matBytes(localGrid_.obstacles) + matBytes(localGrid_.empty);
  total += imageCompressed_.size() + depthOrRightCompressed_.size() + laserScanCompressed_.size() +
           userDataCompressed_.size();
  total += keypoints_.size() * sizeof(cv::KeyPoint) + keypoints3D_.size() * sizeof(cv::Point3f);
  total += cameraModels_.size() * sizeof(CameraModel) +
           stereoCameraModels_.size() * sizeof(StereoCameraModel);
  return total;
}

}  // namespace rtabmap

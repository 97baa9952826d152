#include "VisualInput.h"

#include <opencv2/imgproc.hpp>

#include "rtabmap_core/features/DepthFeatures.h"

namespace rtabmap::odometry_detail {

VisualOdometryOptions VisualOdometryOptions::fromParameters(const ParametersMap& p) {
  VisualOdometryOptions o;
  o.keyFrameThr = Parameters::getFloat(p, Parameters::kOdomKeyFrameThr());
  o.visKeyFrameThr = Parameters::getInt(p, Parameters::kOdomVisKeyFrameThr());
  o.decimation = Parameters::getInt(p, Parameters::kOdomImageDecimation());
  o.fillInfoData = Parameters::getBool(p, Parameters::kOdomFillInfoData());
  return o;
}

bool VisualOdometryOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (keyFrameThr < 0.0f || keyFrameThr > 1.0f) return fail("Odom/KeyFrameThr must be in [0, 1]");
  if (visKeyFrameThr < 0) return fail("Odom/VisKeyFrameThr must not be negative");
  if (decimation < 1) return fail("Odom/ImageDecimation must be at least 1");
  return true;
}

bool VisualOdometryOptions::needsKeyFrame(int inliers, int referenceFeatures) const {
  if (keyFrameThr <= 0.0f || visKeyFrameThr <= 0) return true;
  return static_cast<float>(inliers) < keyFrameThr * static_cast<float>(referenceFeatures) || inliers < visKeyFrameThr;
}

RegistrationVisOptions mapRegistrationOptions(const ParametersMap& parameters) {
  RegistrationVisOptions o = RegistrationVisOptions::fromParameters(parameters);
  o.correspondences.type = 0;
  o.forwardEstOnly = true;
  return o;
}

std::string checkVisualInput(const SensorData& data) {
  if (data.imageRaw().empty()) return "no image in the frame";
  if (data.isStereo()) {
    if (data.depthOrRightRaw().empty()) return "stereo frame without its right image";
    return std::string();
  }
  if (data.cameraModels().empty()) return "no camera model in the frame";
  if (data.depthOrRightRaw().empty()) {
    return "no depth image and no stereo pair: visual odometry needs one of them for 3D features";
  }
  return std::string();
}

namespace {

// Each of the n side-by-side sub-images shrunk by area averaging on its own: shrinking the whole
// image would average pixels across a camera boundary and, when a camera's width is not a
// multiple of the decimation, move the boundaries off the columns the models expect.
cv::Mat shrinkSideBySide(const cv::Mat& image, int n, int decimation) {
  const int w = image.cols / n;
  const cv::Size size(w / decimation, image.rows / decimation);
  std::vector<cv::Mat> parts(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    cv::resize(image.colRange(i * w, (i + 1) * w), parts[static_cast<size_t>(i)], size, 0, 0, cv::INTER_AREA);
  }
  if (n == 1) return parts.front();
  cv::Mat out;
  cv::hconcat(parts, out);
  return out;
}

// The frame shrunk by `decimation` (images by area averaging, depth by picking pixels, camera
// models scaled), or the frame itself for 1.
SensorData decimate(const SensorData& data, int decimation) {
  if (decimation <= 1) return data;
  SensorData out = data;
  const cv::Mat& image = data.imageRaw();
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
  // Depth larger than the shrunk image: pick its pixels (never average depths across edges).
  if (!depth.empty() && depth.cols > size.width && depthDecimationFactor(image.size(), depth.size()) > 0) {
    cv::Mat d;
    cv::resize(depth, d, size, 0, 0, cv::INTER_NEAREST);
    depth = d;
  }
  out.setRGBDImage(small, depth, models);
  return out;
}

}  // namespace

PreparedVisualFrame prepareVisualFrame(SensorData& data, const FeatureDetector& detector, int decimation) {
  PreparedVisualFrame prepared;
  prepared.problem = checkVisualInput(data);
  if (!prepared.problem.empty()) return prepared;
  const SensorData frame = decimate(data, decimation);
  const ImageFeatures features = detector.extract(frame, &prepared.extraction);
  if (!prepared.extraction.problem.empty()) {
    prepared.problem = prepared.extraction.problem;
    return prepared;
  }
  if (features.empty()) {
    prepared.problem = "no features found in the image (no texture, too dark, or masked by invalid depth)";
    return prepared;
  }
  prepared.frame = VisualFrame::fromSensorData(frame, features, detector.options().stereo);
  std::vector<cv::KeyPoint> fullResolution = features.keypoints;
  if (decimation > 1) {
    for (cv::KeyPoint& k : fullResolution) {
      k.pt *= static_cast<float>(decimation);
      k.size *= static_cast<float>(decimation);
    }
  }
  data.setFeatures(fullResolution, features.points3D, features.descriptors);
  return prepared;
}

}  // namespace rtabmap::odometry_detail

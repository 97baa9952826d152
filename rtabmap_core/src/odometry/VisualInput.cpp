#include "VisualInput.h"

#include "rtabmap_core/geometry/ImageDecimation.h"

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

PreparedVisualFrame prepareVisualFrame(SensorData& data, const FeatureDetector& detector, int decimation) {
  PreparedVisualFrame prepared;
  prepared.problem = checkVisualInput(data);
  if (!prepared.problem.empty()) return prepared;
  const SensorData frame = decimateImages(data, decimation);
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
  scaleKeypoints(fullResolution, static_cast<float>(decimation));
  data.setFeatures(fullResolution, features.points3D, features.descriptors);
  return prepared;
}

}  // namespace rtabmap::odometry_detail

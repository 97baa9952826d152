#pragma once
// What F2M and F2F share before registration: checking that a frame can give visual
// odometry, Odom/ImageDecimation, feature extraction, and handing the features back to the
// frame (SensorData::setFeatures, full-resolution keypoints) so the SLAM memory can reuse them
// as visual words (Mem/UseOdomFeatures).
#include <string>

#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/registration/RegistrationVis.h"

namespace rtabmap::odometry_detail {

// Odom/ parameters both visual approaches read.
struct VisualOdometryOptions {
  float keyFrameThr = 0.3f;  // Odom/KeyFrameThr
  int visKeyFrameThr = 150;  // Odom/VisKeyFrameThr
  int decimation = 1;        // Odom/ImageDecimation
  bool fillInfoData = true;  // Odom/FillInfoData

  static VisualOdometryOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
  // A new key frame when the inliers fall under Odom/KeyFrameThr of the reference's features
  // or under Odom/VisKeyFrameThr; either at 0 makes every frame a key frame.
  bool needsKeyFrame(int inliers, int referenceFeatures) const;
};

// Registration options of visual odometry: the Vis/ group as given, with what a registration
// against a feature map cannot do switched off (optical flow needs an image on both sides, a
// backward estimate needs keypoints in the reference).
RegistrationVisOptions mapRegistrationOptions(const ParametersMap& parameters);

struct PreparedVisualFrame {
  VisualFrame frame;  // in the decimated image, when Odom/ImageDecimation > 1
  FeatureExtractionInfo extraction;
  std::string problem;  // non-empty: the frame cannot be used, and why
};

// Empty if the frame has what visual odometry needs (an image, a camera model, depth or a
// stereo pair), else what is missing.
std::string checkVisualInput(const SensorData& data);

PreparedVisualFrame prepareVisualFrame(SensorData& data, const FeatureDetector& detector, int decimation);

}  // namespace rtabmap::odometry_detail

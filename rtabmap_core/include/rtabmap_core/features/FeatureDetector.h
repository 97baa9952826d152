#pragma once
// Keypoint detection and description, for its two users:
//  - visual registration and odometry, configured by the "Vis/" group (Vis/FeatureType,
//    Vis/MaxFeatures, Vis/DepthAsMask, ...);
//  - the loop-closure vocabulary, configured by the "Kp/" group (Kp/DetectorStrategy,
//    Kp/MaxFeatures, Mem/DepthAsMask, ...).
// Both build the same detector from their own group:
//   auto odom = FeatureDetector::create(parameters, FeatureGroup::kVis);
//   auto words = FeatureDetector::create(parameters, FeatureGroup::kKp);
// The detector-specific parameters (GFTT/, ORB/, SIFT/, FAST/, BRISK/, KAZE/, BRIEF/) and the
// stereo correspondence ones (Stereo/) are shared by both.
//
// extract() runs the whole pipeline on a frame (the original's Feature2D::generateKeypoints,
// generateDescriptors and generateKeypoints3D): grey conversion, region of interest, depth mask,
// detection per grid cell keeping the strongest, sub-pixel refinement, description, then the 3D
// point of each keypoint in the robot base frame, from the depth image or by stereo matching.
//
// Several RGB-D cameras (one CameraModel per camera, images side by side: camera i owns the
// columns [i*w, (i+1)*w) of the image, w = width / N, and the same share of the depth image):
// each camera's sub-image is processed alone (its own depth mask, its own model and local
// transform for the 3D points), keypoints are offset into the combined image, and the 3D points
// of all cameras share the base frame. Each camera keeps at most maxFeatures / N keypoints: the
// detectors' responses are not comparable between cameras (exposure, texture), so the
// "strongest overall" would let the most textured view take everything and leave the others
// unconstrained, which is what several cameras are there to avoid (same reason as the grid).
//
// Several stereo cameras (one StereoCameraModel per camera, left images side by side and right
// images side by side the same way): the same split, each camera's keypoints matched for
// disparity in its own right sub-image only (never across a camera boundary), and their 3D
// points through its own model and local transform.
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "rtabmap_core/features/StereoCorrespondences.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

class CameraModel;
class SensorData;
class StereoCameraModel;

// Values of Vis/FeatureType and Kp/DetectorStrategy (the original's numbering; 16 is ours).
enum class FeatureType {
  kSIFT = 1,
  kORB = 2,
  kFastBrief = 4,
  kGfttBrief = 6,
  kBRISK = 7,
  kGfttOrb = 8,
  kKAZE = 9,
  kAKAZE = 16,
};
// "GFTT/ORB", ...; "unknown (N)" for a value outside the enumeration.
std::string featureTypeName(FeatureType type);
// Binary descriptors (ORB, BRIEF, BRISK, AKAZE) are compared by Hamming distance, the others
// (SIFT, KAZE: CV_32F) by Euclidean distance.
bool hasBinaryDescriptors(FeatureType type);

// The parameter group a detector is configured from.
enum class FeatureGroup {
  kVis,  // Vis/FeatureType, Vis/MaxFeatures, Vis/MinDepth, Vis/MaxDepth, Vis/DepthAsMask, ...
  kKp,   // Kp/DetectorStrategy, Kp/MaxFeatures, Kp/MinDepth, Kp/MaxDepth, Mem/DepthAsMask, ...
};

struct FeatureOptions {
  FeatureType type = FeatureType::kGfttOrb;
  // Keep at most this many keypoints, the strongest (0 = no limit, < 0 = extract nothing: the
  // Kp/MaxFeatures convention for "no visual words").
  int maxFeatures = 1000;
  float minDepth = 0.0f;  // m; 0 = no limit
  float maxDepth = 0.0f;  // m; 0 = no limit
  bool depthAsMask = true;
  std::array<double, 4> roiRatios{{0.0, 0.0, 0.0, 0.0}};  // cut from left, right, top, bottom
  int subPixWinSize = 3;
  int subPixIterations = 0;  // 0 = no sub-pixel refinement
  double subPixEps = 0.02;
  int gridRows = 1;
  int gridCols = 1;
  // Values of the detector groups (GFTT/, ORB/, SIFT/, FAST/, BRISK/, KAZE/, BRIEF/), defaults
  // filled in. Read when the detector is built.
  ParametersMap detectorParameters;
  StereoOptions stereo;

  // From the group's parameters (defaults for absent keys). Throws ParameterError on an
  // invalid value.
  static FeatureOptions fromParameters(const ParametersMap& parameters, FeatureGroup group);
  // False (and why) for values no detector can use: unknown type, negative depth range or
  // min >= max, ROI ratios leaving no image, grid of 0 cells, ...
  bool IsValid(std::string* why = nullptr) const;
};

// Features of one image. points3D is empty (no depth nor stereo) or has one point per keypoint,
// in the robot base frame (the camera's local transform applied), NaN where unknown.
struct ImageFeatures {
  std::vector<cv::KeyPoint> keypoints;
  std::vector<cv::Point3f> points3D;
  cv::Mat descriptors;  // one row per keypoint

  size_t size() const { return keypoints.size(); }
  bool empty() const { return keypoints.empty(); }
  // Keypoints with a finite 3D point.
  int validPoints3D() const;
};

// What extract() did, and when it found nothing, why.
struct FeatureExtractionInfo {
  int detected = 0;       // keypoints after the mask, grid and strongest-N
  int described = 0;      // keypoints with a descriptor
  int with3D = 0;         // keypoints with a valid 3D point
  double timeDetectionMs = 0.0;
  double timeDescriptionMs = 0.0;
  double time3DMs = 0.0;
  std::string problem;    // empty when the input was usable; else what was wrong with it
};

class FeatureDetector {
 public:
  // Throws ParameterError if the options are not valid (the message says why).
  explicit FeatureDetector(const FeatureOptions& options);
  ~FeatureDetector();
  FeatureDetector(const FeatureDetector&) = delete;
  FeatureDetector& operator=(const FeatureDetector&) = delete;

  static std::unique_ptr<FeatureDetector> create(const ParametersMap& parameters, FeatureGroup group);

  const FeatureOptions& options() const { return options_; }
  FeatureType type() const { return options_.type; }
  bool binaryDescriptors() const { return hasBinaryDescriptors(options_.type); }

  // Keypoints of an 8-bit grey or BGR image, where `mask` (CV_8UC1, image size, non-zero =
  // allowed; may be empty) allows, inside the region of interest, spread over the grid cells
  // (each keeps its strongest maxFeatures / cells), refined to sub-pixel when asked.
  std::vector<cv::KeyPoint> detect(const cv::Mat& image, const cv::Mat& mask = cv::Mat()) const;
  // Descriptors of the keypoints (one row each). Keypoints for which the descriptor cannot be
  // computed (too close to the border) are removed from `keypoints`.
  cv::Mat compute(const cv::Mat& image, std::vector<cv::KeyPoint>& keypoints) const;

  // The whole pipeline on a frame (mono, RGB-D or stereo). Never throws on bad sensor data:
  // an unusable frame returns no features and says why in info->problem (no image, unsupported
  // image type, invalid camera model, depth size not a whole fraction of the image, no valid
  // depth at all).
  ImageFeatures extract(const SensorData& data, FeatureExtractionInfo* info = nullptr) const;

 private:
  std::vector<cv::KeyPoint> detectUpTo(const cv::Mat& grey, const cv::Mat& mask, int maxFeatures) const;
  // Features of one RGB-D (or mono, empty depth) camera image with at most maxFeatures
  // keypoints; empty with *problem set when its depth is unusable.
  ImageFeatures extractDepthCamera(const cv::Mat& grey, const cv::Mat& depth, const CameraModel* model,
                                   int maxFeatures, FeatureExtractionInfo& info, std::string* problem) const;
  ImageFeatures extractSeveralCameras(const SensorData& data, const cv::Mat& grey, FeatureExtractionInfo& info) const;
  // Features of one rectified stereo camera (3D points by disparity along each keypoint's row);
  // empty with *problem set when its model cannot project.
  ImageFeatures extractStereoCamera(const cv::Mat& grey, const cv::Mat& rightGrey, const StereoCameraModel& model,
                                    int maxFeatures, FeatureExtractionInfo& info, std::string* problem) const;
  ImageFeatures extractSeveralStereoCameras(const SensorData& data, const cv::Mat& grey, const cv::Mat& rightGrey,
                                            FeatureExtractionInfo& info) const;

  struct Impl;
  FeatureOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rtabmap

#pragma once
// Fiducial markers (ArUco, AprilTag) as landmarks of the graph: RGBD/MarkerDetection and the
// Marker/ group. Each marker found in a frame's images (OpenCV's aruco module) becomes a
// Landmark: its pose in the robot base frame from the four corners (PnP on a square of side
// Marker/Length), with the covariance of Marker/VarianceLinear and Marker/VarianceAngular.
//
// Marker/Length 0: the side is measured, once per marker id, from the depth image the first
// time the marker is seen facing the camera (its four corners within Marker/MaxDepthError of
// each other in depth), and kept for every later sighting; until then the marker is skipped
// (a pose needs a scale). Stereo frames have no depth image: they need Marker/Length.
// Marker id 0 is never a landmark (its graph node would be 0), as in the original: use ids >= 1.
//
//   MarkerDetector detector(MarkerDetectorOptions::fromParameters(parameters));
//   Landmarks seen = detector.detect(frame);  // raw images and camera models
#include <map>
#include <memory>
#include <string>

#include "rtabmap_core/geometry/Landmark.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

class SensorData;

struct MarkerDetectorOptions {
  int dictionary = 0;             // Marker/Dictionary: OpenCV's predefined dictionaries 0-20
  float length = 0.0f;            // Marker/Length (m), 0 = measured from depth
  float maxDepthError = 0.01f;    // Marker/MaxDepthError (m)
  float varianceLinear = 0.001f;  // Marker/VarianceLinear (m^2)
  float varianceAngular = 0.01f;  // Marker/VarianceAngular (rad^2), >= 9999: position only
  int cornerRefinementMethod = 0; // Marker/CornerRefinementMethod: 0 none, 1 subpixel, 2 contour, 3 AprilTag
  float maxRange = 0.0f;          // Marker/MaxRange (m), 0 = no limit
  float minRange = 0.0f;          // Marker/MinRange (m), 0 = no limit

  // Missing keys take their declared defaults; a value out of its declared range is a
  // ParameterError naming the key.
  static MarkerDetectorOptions fromParameters(const ParametersMap& parameters);
  // False, with the reason naming the parameter key: unknown dictionary or refinement, negative
  // or non-finite length, ranges or variances, MinRange above MaxRange.
  bool IsValid(std::string* why = nullptr) const;
};

struct MarkerDetectionInfo {
  int detected = 0;            // markers decoded in the images
  int withoutLength = 0;       // skipped: Marker/Length 0 and no measured side yet
  int outOfRange = 0;          // skipped: nearer than MinRange or farther than MaxRange
  int idZero = 0;              // skipped: marker id 0 (a landmark's graph node is -id)
  std::string problem;         // why nothing could be looked for (no image, no camera model)
};

class MarkerDetector {
 public:
  // Throws ParameterError when !options.IsValid().
  explicit MarkerDetector(const MarkerDetectorOptions& options);
  ~MarkerDetector();
  MarkerDetector(const MarkerDetector&) = delete;
  MarkerDetector& operator=(const MarkerDetector&) = delete;

  // The markers seen in the frame's raw image (several cameras side by side: each camera's part
  // with its own model). Needs raw images; a frame without image or camera model gives none.
  Landmarks detect(const SensorData& frame, MarkerDetectionInfo* info = nullptr);

  // Side lengths measured so far (Marker/Length 0), by marker id.
  const std::map<int, float>& measuredLengths() const { return measuredLengths_; }
  const MarkerDetectorOptions& options() const { return options_; }

 private:
  struct Detector;
  MarkerDetectorOptions options_;
  std::map<int, float> measuredLengths_;
  std::unique_ptr<Detector> detector_;  // OpenCV's dictionary and detector parameters, kept out of this header
};

}  // namespace rtabmap

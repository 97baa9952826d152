#pragma once
// How each node's local occupancy grid is made (JFR 2019, section 4.3.3): the Grid/* parameters
// as a struct, with the Ceres-style check IsValid(why). Stereo pairs first become depth by
// OpenCV block matching (StereoBM/* parameters), then follow the depth path.
//
//   LocalGridOptions options = LocalGridOptions::fromParameters(parameters);  // ParameterError
//   std::string why;
//   if (!options.IsValid(&why)) ...                                          // for hand-made ones
#include <array>
#include <string>

#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

// StereoBM/*: dense disparity of a rectified pair (cv::StereoBM).
struct StereoBMOptions {
  int blockSize = 15;
  int minDisparity = 0;
  int numDisparities = 128;
  int preFilterSize = 9;
  int preFilterCap = 31;
  int uniquenessRatio = 15;
  int textureThreshold = 10;
  int speckleWindowSize = 100;
  int speckleRange = 4;
  int disp12MaxDiff = -1;

  static StereoBMOptions fromParameters(const ParametersMap& parameters);
  // OpenCV's own constraints (odd block size >= 5, numDisparities a positive multiple of 16...),
  // named by parameter key.
  bool IsValid(std::string* why = nullptr) const;
};

struct LocalGridOptions {
  // Grid/Sensor.
  enum class Sensor { kScan = 0, kDepth = 1, kBoth = 2 };
  Sensor sensor = Sensor::kDepth;
  float cellSize = 0.05f;            // Grid/CellSize (m)
  float rangeMin = 0.0f;             // Grid/RangeMin (m)
  float rangeMax = 5.0f;             // Grid/RangeMax (m), 0 = none
  bool grid3D = true;                // Grid/3D
  bool rayTracing = false;           // Grid/RayTracing
  int depthDecimation = 4;           // Grid/DepthDecimation
  std::array<float, 4> depthRoiRatios{{0.f, 0.f, 0.f, 0.f}};  // Grid/DepthRoiRatios l r t b
  int scanDecimation = 1;            // Grid/ScanDecimation
  float footprintLength = 0.0f;      // Grid/FootprintLength (m)
  float footprintWidth = 0.0f;       // Grid/FootprintWidth (m)
  float footprintHeight = 0.0f;      // Grid/FootprintHeight (m)
  bool preVoxelFiltering = true;     // Grid/PreVoxelFiltering
  bool mapFrameProjection = false;   // Grid/MapFrameProjection
  bool normalsSegmentation = true;   // Grid/NormalsSegmentation
  float maxGroundAngle = 45.0f;      // Grid/MaxGroundAngle (degrees)
  int normalK = 20;                  // Grid/NormalK
  float clusterRadius = 0.1f;        // Grid/ClusterRadius (m)
  int minClusterSize = 10;           // Grid/MinClusterSize
  bool flatObstacleDetected = true;  // Grid/FlatObstacleDetected
  float minGroundHeight = 0.0f;      // Grid/MinGroundHeight (m), 0 = disabled
  float maxGroundHeight = 0.0f;      // Grid/MaxGroundHeight (m), 0 = disabled
  float maxObstacleHeight = 0.0f;    // Grid/MaxObstacleHeight (m), 0 = disabled
  bool groundIsObstacle = false;     // Grid/GroundIsObstacle
  float noiseFilteringRadius = 0.0f; // Grid/NoiseFilteringRadius (m), 0 = disabled
  int noiseFilteringMinNeighbors = 5;  // Grid/NoiseFilteringMinNeighbors
  bool scan2dUnknownSpaceFilled = false;  // Grid/Scan2dUnknownSpaceFilled
  StereoBMOptions stereo;            // StereoBM/*

  // Missing keys take their declared defaults; an invalid value (a cell size of 0, ...) is a
  // ParameterError naming the key.
  static LocalGridOptions fromParameters(const ParametersMap& parameters);
  // False, with the reason naming the parameter key, when a field is unusable: cell size <= 0
  // or not finite, RangeMax <= RangeMin (when set), decimations < 1, ROI ratios leaving no
  // image, a depth path without any way to tell ground (no normals and no MaxGroundHeight,
  // unless Grid/GroundIsObstacle), invalid stereo settings...
  bool IsValid(std::string* why = nullptr) const;
  // Throws ParameterError with IsValid's reason.
  void validate() const;

  bool usesScan() const { return sensor != Sensor::kDepth; }
  bool usesDepth() const { return sensor != Sensor::kScan; }
  bool hasFootprint() const { return footprintLength > 0.0f; }
};

}  // namespace rtabmap

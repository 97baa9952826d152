#include "rtabmap_core/maps/LocalGridOptions.h"

#include <cmath>
#include <sstream>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {

namespace {
bool finiteAtLeast(float v, float lo) { return std::isfinite(v) && v >= lo; }
}  // namespace

StereoBMOptions StereoBMOptions::fromParameters(const ParametersMap& p) {
  StereoBMOptions o;
  o.blockSize = Parameters::getInt(p, Parameters::kStereoBMBlockSize());
  o.minDisparity = Parameters::getInt(p, Parameters::kStereoBMMinDisparity());
  o.numDisparities = Parameters::getInt(p, Parameters::kStereoBMNumDisparities());
  o.preFilterSize = Parameters::getInt(p, Parameters::kStereoBMPreFilterSize());
  o.preFilterCap = Parameters::getInt(p, Parameters::kStereoBMPreFilterCap());
  o.uniquenessRatio = Parameters::getInt(p, Parameters::kStereoBMUniquenessRatio());
  o.textureThreshold = Parameters::getInt(p, Parameters::kStereoBMTextureThreshold());
  o.speckleWindowSize = Parameters::getInt(p, Parameters::kStereoBMSpeckleWindowSize());
  o.speckleRange = Parameters::getInt(p, Parameters::kStereoBMSpeckleRange());
  o.disp12MaxDiff = Parameters::getInt(p, Parameters::kStereoBMDisp12MaxDiff());
  return o;
}

bool StereoBMOptions::IsValid(std::string* why) const {
  std::ostringstream r;
  // cv::StereoBM asserts on these; say it in parameter terms before OpenCV does.
  if (blockSize < 5 || blockSize > 255 || blockSize % 2 == 0) {
    r << "StereoBM/BlockSize must be odd, between 5 and 255 (got " << blockSize << ")";
  } else if (numDisparities < 16 || numDisparities % 16 != 0) {
    r << "StereoBM/NumDisparities must be a positive multiple of 16 (got " << numDisparities << ")";
  } else if (preFilterSize < 5 || preFilterSize > 255 || preFilterSize % 2 == 0) {
    r << "StereoBM/PreFilterSize must be odd, between 5 and 255 (got " << preFilterSize << ")";
  } else if (preFilterCap < 1 || preFilterCap > 63) {
    r << "StereoBM/PreFilterCap must be between 1 and 63 (got " << preFilterCap << ")";
  } else if (uniquenessRatio < 0 || textureThreshold < 0 || speckleWindowSize < 0 ||
             speckleRange < 0) {
    r << "StereoBM/UniquenessRatio, TextureThreshold, SpeckleWindowSize and SpeckleRange must be "
         ">= 0";
  }
  const std::string text = r.str();
  if (why) *why = text;
  return text.empty();
}

LocalGridOptions LocalGridOptions::fromParameters(const ParametersMap& p) {
  LocalGridOptions o;
  o.sensor = static_cast<Sensor>(Parameters::getInt(p, Parameters::kGridSensor()));
  o.cellSize = Parameters::getFloat(p, Parameters::kGridCellSize());
  o.rangeMin = Parameters::getFloat(p, Parameters::kGridRangeMin());
  o.rangeMax = Parameters::getFloat(p, Parameters::kGridRangeMax());
  o.grid3D = Parameters::getBool(p, Parameters::kGrid3D());
  o.rayTracing = Parameters::getBool(p, Parameters::kGridRayTracing());
  o.depthDecimation = Parameters::getInt(p, Parameters::kGridDepthDecimation());
  const std::vector<double> roi = Parameters::getNumberList(p, Parameters::kGridDepthRoiRatios());
  for (size_t i = 0; i < 4 && i < roi.size(); ++i) o.depthRoiRatios[i] = static_cast<float>(roi[i]);
  o.scanDecimation = Parameters::getInt(p, Parameters::kGridScanDecimation());
  o.footprintLength = Parameters::getFloat(p, Parameters::kGridFootprintLength());
  o.footprintWidth = Parameters::getFloat(p, Parameters::kGridFootprintWidth());
  o.footprintHeight = Parameters::getFloat(p, Parameters::kGridFootprintHeight());
  o.preVoxelFiltering = Parameters::getBool(p, Parameters::kGridPreVoxelFiltering());
  o.mapFrameProjection = Parameters::getBool(p, Parameters::kGridMapFrameProjection());
  o.normalsSegmentation = Parameters::getBool(p, Parameters::kGridNormalsSegmentation());
  o.maxGroundAngle = Parameters::getFloat(p, Parameters::kGridMaxGroundAngle());
  o.normalK = Parameters::getInt(p, Parameters::kGridNormalK());
  o.clusterRadius = Parameters::getFloat(p, Parameters::kGridClusterRadius());
  o.minClusterSize = Parameters::getInt(p, Parameters::kGridMinClusterSize());
  o.flatObstacleDetected = Parameters::getBool(p, Parameters::kGridFlatObstacleDetected());
  o.minGroundHeight = Parameters::getFloat(p, Parameters::kGridMinGroundHeight());
  o.maxGroundHeight = Parameters::getFloat(p, Parameters::kGridMaxGroundHeight());
  o.maxObstacleHeight = Parameters::getFloat(p, Parameters::kGridMaxObstacleHeight());
  o.groundIsObstacle = Parameters::getBool(p, Parameters::kGridGroundIsObstacle());
  o.noiseFilteringRadius = Parameters::getFloat(p, Parameters::kGridNoiseFilteringRadius());
  o.noiseFilteringMinNeighbors = Parameters::getInt(p, Parameters::kGridNoiseFilteringMinNeighbors());
  o.scan2dUnknownSpaceFilled = Parameters::getBool(p, Parameters::kGridScan2dUnknownSpaceFilled());
  o.stereo = StereoBMOptions::fromParameters(p);
  return o;
}

bool LocalGridOptions::IsValid(std::string* why) const {
  std::ostringstream r;
  const int s = static_cast<int>(sensor);
  if (s < 0 || s > 2) {
    r << "Grid/Sensor must be 0 (laser scan), 1 (depth image) or 2 (both) (got " << s << ")";
  } else if (!(std::isfinite(cellSize) && cellSize > 0.0f)) {
    r << "Grid/CellSize must be a finite number > 0 (got " << cellSize << ")";
  } else if (!finiteAtLeast(rangeMin, 0.0f) || !finiteAtLeast(rangeMax, 0.0f)) {
    r << "Grid/RangeMin and Grid/RangeMax must be finite and >= 0 (got " << rangeMin << ", "
      << rangeMax << ")";
  } else if (rangeMax > 0.0f && rangeMax <= rangeMin) {
    r << "Grid/RangeMax (" << rangeMax << ") must be greater than Grid/RangeMin (" << rangeMin
      << "), or 0 for no limit";
  } else if (depthDecimation < 1) {
    r << "Grid/DepthDecimation must be at least 1 (got " << depthDecimation << ")";
  } else if (scanDecimation < 1) {
    r << "Grid/ScanDecimation must be at least 1 (got " << scanDecimation << ")";
  } else if (!(depthRoiRatios[0] >= 0 && depthRoiRatios[1] >= 0 && depthRoiRatios[2] >= 0 &&
               depthRoiRatios[3] >= 0 && depthRoiRatios[0] + depthRoiRatios[1] < 1.0f &&
               depthRoiRatios[2] + depthRoiRatios[3] < 1.0f)) {
    r << "Grid/DepthRoiRatios must be four fractions >= 0 whose left + right and top + bottom "
         "are each < 1 (they would leave no image)";
  } else if (!finiteAtLeast(footprintLength, 0.0f) || !finiteAtLeast(footprintWidth, 0.0f) ||
             !finiteAtLeast(footprintHeight, 0.0f)) {
    r << "Grid/FootprintLength, Grid/FootprintWidth and Grid/FootprintHeight must be >= 0";
  } else if (footprintLength == 0.0f && (footprintWidth > 0.0f || footprintHeight > 0.0f)) {
    r << "Grid/FootprintWidth and Grid/FootprintHeight need Grid/FootprintLength > 0";
  } else if (!(maxGroundAngle >= 0.0f && maxGroundAngle <= 90.0f)) {
    r << "Grid/MaxGroundAngle must be between 0 and 90 degrees (got " << maxGroundAngle << ")";
  } else if (normalK < 1) {
    r << "Grid/NormalK must be at least 1 (got " << normalK << ")";
  } else if (!(std::isfinite(clusterRadius) && clusterRadius > 0.0f)) {
    r << "Grid/ClusterRadius must be a finite number > 0 (got " << clusterRadius << ")";
  } else if (minClusterSize < 0) {
    r << "Grid/MinClusterSize must be >= 0 (got " << minClusterSize << ")";
  } else if (!std::isfinite(minGroundHeight) || !std::isfinite(maxGroundHeight) ||
             !std::isfinite(maxObstacleHeight)) {
    r << "Grid/MinGroundHeight, Grid/MaxGroundHeight and Grid/MaxObstacleHeight must be finite";
  } else if (maxObstacleHeight != 0.0f && maxGroundHeight != 0.0f &&
             maxObstacleHeight <= maxGroundHeight) {
    r << "Grid/MaxObstacleHeight (" << maxObstacleHeight
      << ") must be above Grid/MaxGroundHeight (" << maxGroundHeight << ")";
  } else if (minGroundHeight != 0.0f && maxGroundHeight != 0.0f &&
             minGroundHeight >= maxGroundHeight) {
    r << "Grid/MinGroundHeight (" << minGroundHeight << ") must be below Grid/MaxGroundHeight ("
      << maxGroundHeight << ")";
  } else if (usesDepth() && !normalsSegmentation && maxGroundHeight == 0.0f && !groundIsObstacle) {
    // Without normals, height is the only way to tell the floor: with neither, every point of a
    // depth image would be an obstacle and the floor in front of the robot would block it.
    r << "Grid/NormalsSegmentation is false, so Grid/MaxGroundHeight must be set (the height "
         "under which points are ground), or Grid/GroundIsObstacle true";
  } else if (!finiteAtLeast(noiseFilteringRadius, 0.0f)) {
    r << "Grid/NoiseFilteringRadius must be >= 0 (got " << noiseFilteringRadius << ")";
  } else if (noiseFilteringMinNeighbors < 1) {
    r << "Grid/NoiseFilteringMinNeighbors must be at least 1 (got " << noiseFilteringMinNeighbors
      << ")";
  } else {
    std::string stereoWhy;
    if (!stereo.IsValid(&stereoWhy)) r << stereoWhy;
  }
  const std::string text = r.str();
  if (why) *why = text;
  return text.empty();
}

void LocalGridOptions::validate() const {
  std::string why;
  if (!IsValid(&why)) throw ParameterError("invalid local grid options: " + why);
}

}  // namespace rtabmap

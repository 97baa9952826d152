#include <cmath>
#include <sstream>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/features/FeatureDetector.h"

namespace rtabmap {

std::string featureTypeName(FeatureType type) {
  switch (type) {
    case FeatureType::kSIFT: return "SIFT";
    case FeatureType::kORB: return "ORB";
    case FeatureType::kFastBrief: return "FAST/BRIEF";
    case FeatureType::kGfttBrief: return "GFTT/BRIEF";
    case FeatureType::kBRISK: return "BRISK";
    case FeatureType::kGfttOrb: return "GFTT/ORB";
    case FeatureType::kKAZE: return "KAZE";
    case FeatureType::kAKAZE: return "AKAZE";
  }
  return "unknown (" + std::to_string(static_cast<int>(type)) + ")";
}

bool hasBinaryDescriptors(FeatureType type) {
  return type != FeatureType::kSIFT && type != FeatureType::kKAZE;
}

namespace {

// Keys of the detector-specific groups, copied with their defaults into detectorParameters so
// the detector reads every value from one validated map.
const char* const kDetectorGroups[] = {"GFTT", "ORB", "SIFT", "FAST", "BRISK", "KAZE", "BRIEF"};

std::array<double, 4> roiFrom(const ParametersMap& p, const std::string& key) {
  const std::vector<double> v = Parameters::getNumberList(p, key);
  std::array<double, 4> r{{0.0, 0.0, 0.0, 0.0}};
  for (size_t i = 0; i < 4 && i < v.size(); ++i) r[i] = v[i];
  return r;
}

}  // namespace

FeatureOptions FeatureOptions::fromParameters(const ParametersMap& p, FeatureGroup group) {
  FeatureOptions o;
  if (group == FeatureGroup::kVis) {
    o.type = static_cast<FeatureType>(Parameters::getInt(p, Parameters::kVisFeatureType()));
    o.maxFeatures = Parameters::getInt(p, Parameters::kVisMaxFeatures());
    o.minDepth = Parameters::getFloat(p, Parameters::kVisMinDepth());
    o.maxDepth = Parameters::getFloat(p, Parameters::kVisMaxDepth());
    o.depthAsMask = Parameters::getBool(p, Parameters::kVisDepthAsMask());
    o.roiRatios = roiFrom(p, Parameters::kVisRoiRatios());
    o.subPixWinSize = Parameters::getInt(p, Parameters::kVisSubPixWinSize());
    o.subPixIterations = Parameters::getInt(p, Parameters::kVisSubPixIterations());
    o.subPixEps = Parameters::getDouble(p, Parameters::kVisSubPixEps());
    o.gridRows = Parameters::getInt(p, Parameters::kVisGridRows());
    o.gridCols = Parameters::getInt(p, Parameters::kVisGridCols());
  } else {
    o.type = static_cast<FeatureType>(Parameters::getInt(p, Parameters::kKpDetectorStrategy()));
    o.maxFeatures = Parameters::getInt(p, Parameters::kKpMaxFeatures());
    o.minDepth = Parameters::getFloat(p, Parameters::kKpMinDepth());
    o.maxDepth = Parameters::getFloat(p, Parameters::kKpMaxDepth());
    o.depthAsMask = Parameters::getBool(p, Parameters::kMemDepthAsMask());
    o.roiRatios = roiFrom(p, Parameters::kKpRoiRatios());
    o.subPixWinSize = Parameters::getInt(p, Parameters::kKpSubPixWinSize());
    o.subPixIterations = Parameters::getInt(p, Parameters::kKpSubPixIterations());
    o.subPixEps = Parameters::getDouble(p, Parameters::kKpSubPixEps());
    o.gridRows = Parameters::getInt(p, Parameters::kKpGridRows());
    o.gridCols = Parameters::getInt(p, Parameters::kKpGridCols());
  }
  const ParametersMap all = Parameters::withDefaults(p);
  for (const char* g : kDetectorGroups) {
    const ParametersMap groupValues = Parameters::filterByGroup(all, g);
    o.detectorParameters.insert(groupValues.begin(), groupValues.end());
  }
  o.stereo = StereoOptions::fromParameters(p);
  return o;
}

bool FeatureOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  switch (type) {
    case FeatureType::kSIFT: case FeatureType::kORB: case FeatureType::kFastBrief:
    case FeatureType::kGfttBrief: case FeatureType::kBRISK: case FeatureType::kGfttOrb:
    case FeatureType::kKAZE: case FeatureType::kAKAZE:
      break;
    default:
      return fail("feature type " + std::to_string(static_cast<int>(type)) +
                  " is not available (1 SIFT, 2 ORB, 4 FAST/BRIEF, 6 GFTT/BRIEF, 7 BRISK, 8 GFTT/ORB, 9 KAZE, 16 AKAZE)");
  }
  if (minDepth < 0.0f || maxDepth < 0.0f) return fail("depth limits must not be negative");
  if (maxDepth > 0.0f && minDepth >= maxDepth) {
    std::ostringstream s;
    s << "minimum depth " << minDepth << " m must be under the maximum depth " << maxDepth << " m";
    return fail(s.str());
  }
  for (double r : roiRatios) {
    if (!(r >= 0.0 && r < 1.0)) return fail("ROI ratios must be in [0, 1)");
  }
  if (roiRatios[0] + roiRatios[1] >= 1.0 || roiRatios[2] + roiRatios[3] >= 1.0) {
    return fail("ROI ratios cut the whole image away (left + right and top + bottom must stay under 1)");
  }
  if (subPixWinSize < 1) return fail("sub-pixel window size must be at least 1");
  if (subPixIterations < 0) return fail("sub-pixel iterations must not be negative");
  if (!(subPixEps > 0.0)) return fail("sub-pixel epsilon must be positive");
  if (gridRows < 1 || gridCols < 1) return fail("the feature grid needs at least 1 row and 1 column");
  std::string stereoWhy;
  if (!stereo.IsValid(&stereoWhy)) return fail(stereoWhy);
  return true;
}

int ImageFeatures::validPoints3D() const {
  int n = 0;
  for (const cv::Point3f& p : points3D) {
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) ++n;
  }
  return n;
}

}  // namespace rtabmap

#include "rtabmap_odom/NodeParameters.h"

#include <cstdio>

#include "rtabmap_core/params/ClosestMatch.h"

namespace rtabmap_odom {

namespace {

bool isCoreKey(const std::string& name) { return name.find('/') != std::string::npos; }

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", v);
  return text;
}

}  // namespace

CoreParameters coreParametersFromPrivate(const std::map<std::string, std::string>& raw) {
  CoreParameters out;
  for (const auto& [key, value] : raw) {
    if (!isCoreKey(key)) continue;
    if (!rtabmap::Parameters::isDeclared(key)) {
      out.warnings.push_back("unknown parameter \"" + key + "\" ignored (did you mean \"" +
                             rtabmap::Parameters::closestKey(key) + "\"?)");
      continue;
    }
    std::string why;
    if (!rtabmap::Parameters::isValid(key, value, &why)) {
      out.warnings.push_back("parameter \"" + key + "\" = \"" + value + "\" ignored: " + why + " (default " +
                             rtabmap::Parameters::info(key).defaultValue + " used)");
      continue;
    }
    out.parameters[key] = value;
  }
  return out;
}

std::vector<std::string> unknownNodeParameters(const std::map<std::string, std::string>& raw,
                                               const std::vector<std::string>& known) {
  std::vector<std::string> warnings;
  for (const auto& entry : raw) {
    const std::string& name = entry.first;
    if (isCoreKey(name)) continue;
    bool isKnown = false;
    for (const std::string& k : known) isKnown = isKnown || k == name;
    if (!isKnown) {
      warnings.push_back("unknown parameter \"" + name + "\" ignored (did you mean \"" +
                         rtabmap::closestMatch(name, known) + "\"?)");
    }
  }
  return warnings;
}

bool ScanOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (rangeMin < 0.0) return fail("scan_range_min must be >= 0 (got " + number(rangeMin) + ")");
  if (rangeMax < 0.0) return fail("scan_range_max must be >= 0 (got " + number(rangeMax) + ")");
  if (rangeMax > 0.0 && rangeMin >= rangeMax) {
    return fail("scan_range_min (" + number(rangeMin) + ") must be below scan_range_max (" + number(rangeMax) + ")");
  }
  if (voxelSize < 0.0) return fail("scan_voxel_size must be >= 0 (got " + number(voxelSize) + ")");
  if (downsamplingStep < 1) return fail("scan_downsampling_step must be >= 1 (got " + number(downsamplingStep) + ")");
  if (normalK < 0) return fail("scan_normal_k must be >= 0 (got " + number(normalK) + ")");
  if (normalRadius < 0.0) return fail("scan_normal_radius must be >= 0 (got " + number(normalRadius) + ")");
  return true;
}

rtabmap::ParametersMap applyScanOptions(const ScanOptions& options, const rtabmap::ParametersMap& parameters,
                                        std::vector<std::string>* notes) {
  using P = rtabmap::Parameters;
  rtabmap::ParametersMap out = parameters;
  auto set = [&](const char* node, bool given, const std::string& key, const std::string& value) {
    if (!given) return;
    auto it = parameters.find(key);
    if (it != parameters.end()) {
      if (notes && it->second != value) {
        notes->push_back(std::string(node) + " (" + value + ") ignored: " + key + " is set to " + it->second);
      }
      return;
    }
    out[key] = value;
  };
  set("scan_range_min", options.rangeMin > 0.0, P::kIcpRangeMin(), number(options.rangeMin));
  set("scan_range_max", options.rangeMax > 0.0, P::kIcpRangeMax(), number(options.rangeMax));
  set("scan_voxel_size", options.voxelSize > 0.0, P::kIcpVoxelSize(), number(options.voxelSize));
  set("scan_downsampling_step", options.downsamplingStep > 1, P::kIcpDownsamplingStep(),
      std::to_string(options.downsamplingStep));
  set("scan_normal_k", options.normalK > 0, P::kIcpPointToPlaneK(), std::to_string(options.normalK));
  set("scan_normal_radius", options.normalRadius > 0.0, P::kIcpPointToPlaneRadius(), number(options.normalRadius));
  return out;
}

}  // namespace rtabmap_odom

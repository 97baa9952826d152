#include "rtabmap_slam_node/InitialPoseParam.h"

#include <cmath>
#include <cstdlib>
#include <vector>

namespace rtabmap_slam_node {
namespace {

std::optional<rtabmap::Transform> fail(std::string* why, const std::string& reason) {
  if (why) *why = reason;
  return std::nullopt;
}

// The whitespace- or comma-separated tokens of `text`.
std::vector<std::string> tokens(const std::string& text) {
  std::vector<std::string> out;
  std::string current;
  for (char c : text + " ") {
    if (c == ' ' || c == ',' || c == '\t' || c == '\n') {
      if (!current.empty()) out.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  return out;
}

}  // namespace

std::optional<rtabmap::Transform> parseInitialPose(const std::string& text, std::string* why) {
  if (why) why->clear();
  const std::vector<std::string> words = tokens(text);
  if (words.empty()) return std::nullopt;
  const std::string expected = "\"x y z roll pitch yaw\" or \"x y z qx qy qz qw\"";
  if (words.size() != 6 && words.size() != 7) {
    return fail(why, "\"" + text + "\" has " + std::to_string(words.size()) + " values; expected " + expected);
  }
  std::vector<double> v;
  for (const std::string& w : words) {
    char* end = nullptr;
    const double d = std::strtod(w.c_str(), &end);
    if (end == w.c_str() || *end != '\0' || !std::isfinite(d)) {
      return fail(why, "\"" + w + "\" in \"" + text + "\" is not a finite number; expected " + expected);
    }
    v.push_back(d);
  }
  if (v.size() == 6) return rtabmap::Transform(v[0], v[1], v[2], v[3], v[4], v[5]);
  const double norm = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
  if (norm < 1e-6) return fail(why, "the quaternion of \"" + text + "\" is zero");
  return rtabmap::Transform(v[0], v[1], v[2], v[3] / norm, v[4] / norm, v[5] / norm, v[6] / norm);
}

}  // namespace rtabmap_slam_node

#include "rtabmap_slam_node/InitialPoseParam.h"

#include <sstream>

#include "rtabmap_core/common/Error.h"

namespace rtabmap_slam_node {

std::optional<rtabmap::Transform> parseInitialPose(const std::string& text, std::string* why) {
  if (why) why->clear();
  // Transform::fromString reads the numbers; the parameter only takes its 6- and 7-value forms
  // (x y theta or a 3x4 matrix would be ambiguous in a launch file).
  std::string spaced = text;
  for (char& c : spaced) {
    if (c == ',') c = ' ';
  }
  std::istringstream words(spaced);
  size_t count = 0;
  for (std::string w; words >> w;) ++count;
  if (count == 0) return std::nullopt;
  const auto fail = [why](const std::string& reason) -> std::optional<rtabmap::Transform> {
    if (why) *why = reason;
    return std::nullopt;
  };
  if (count != 6 && count != 7) {
    return fail("\"" + text + "\" has " + std::to_string(count) +
                " values; expected \"x y z roll pitch yaw\" or \"x y z qx qy qz qw\"");
  }
  try {
    return rtabmap::Transform::fromString(text);
  } catch (const rtabmap::FormatError& e) {
    return fail(e.what());
  }
}

}  // namespace rtabmap_slam_node

#include "rtabmap_conversions/LaserScanConversions.h"

#include <cmath>
#include <limits>

#include "Support.h"

namespace rtabmap_conversions {

std::optional<rtabmap::LaserScan> laserScanFromMsg(const sensor_msgs::LaserScan& msg,
                                                   const rtabmap::Transform& localTransform, std::string* error) {
  const std::string what = "LaserScan of frame '" + msg.header.frame_id + "'";
  if (msg.ranges.empty()) return detail::fail(error, what + " has no ranges");
  if (!std::isfinite(msg.angle_min) || !std::isfinite(msg.angle_max) || !std::isfinite(msg.angle_increment) ||
      msg.angle_increment == 0.0f) {
    return detail::fail(error, what + " has an invalid beam geometry (angle_min " + std::to_string(msg.angle_min) +
                                   ", angle_max " + std::to_string(msg.angle_max) + ", angle_increment " +
                                   std::to_string(msg.angle_increment) + ")");
  }
  // Fuzzing fix (fuzz/regressions/ros_laser_scan): angles of 1e30 rad passed, and the core's
  // bearing unwrapping (LaserScan::toRanges adds 2 pi until in range) then never ended. A laser's
  // beams lie within a couple of turns of zero (REP-103 angles: [-pi, pi], some drivers [0, 2 pi]).
  constexpr double kMaxAngle = 4.0 * M_PI;
  if (std::abs(msg.angle_min) > kMaxAngle || std::abs(msg.angle_max) > kMaxAngle) {
    return detail::fail(error, what + " has beam angles beyond +-4 pi (angle_min " + std::to_string(msg.angle_min) +
                                   ", angle_max " + std::to_string(msg.angle_max) + ")");
  }
  // Drivers disagree on whether angle_max is the last beam or one past it: accept one beam of
  // slack, reject anything else (a wrong increment would put every point at a wrong bearing).
  const double span = (double(msg.angle_max) - double(msg.angle_min)) / double(msg.angle_increment);
  // Fuzzing fix (fuzz/regressions/ros_laser_scan): a tiny increment made span too large for
  // std::lround (undefined, then a signed overflow): bound it by the range count first.
  const bool spanFits = span >= -0.5 && span <= double(msg.ranges.size()) + 1.0;
  const long expected = spanFits ? std::lround(span) + 1 : 0;
  if (!spanFits || std::abs(expected - long(msg.ranges.size())) > 1) {
    return detail::fail(error, what + ": angles from " + std::to_string(msg.angle_min) + " to " +
                                   std::to_string(msg.angle_max) + " by " + std::to_string(msg.angle_increment) +
                                   " make " + std::to_string(span + 1.0) + " beams, but there are " +
                                   std::to_string(msg.ranges.size()) + " ranges");
  }
  if (!std::isfinite(msg.range_min) || !std::isfinite(msg.range_max) || msg.range_min < 0.0f ||
      msg.range_max <= msg.range_min) {
    return detail::fail(error, what + " has invalid range limits [" + std::to_string(msg.range_min) + ", " +
                                   std::to_string(msg.range_max) + "]");
  }
  if (!msg.intensities.empty() && msg.intensities.size() != msg.ranges.size()) {
    return detail::fail(error, what + " has " + std::to_string(msg.intensities.size()) + " intensities for " +
                                   std::to_string(msg.ranges.size()) + " ranges");
  }
  try {
    return rtabmap::LaserScan::fromRanges(msg.ranges, msg.angle_min, msg.angle_increment, msg.range_min,
                                          msg.range_max, localTransform, msg.intensities);
  } catch (const std::exception& e) {
    return detail::fail(error, what + ": " + e.what());
  }
}

std::optional<sensor_msgs::LaserScan> laserScanToMsg(const rtabmap::LaserScan& scan, const std_msgs::Header& header,
                                                     std::string* error) {
  if (!scan.is2d() && !scan.empty()) {
    return detail::fail(error, "laserScanToMsg: a " + rtabmap::LaserScan::formatName(scan.format()) +
                                   " scan is 3D; publish it as a PointCloud2");
  }
  if (!scan.hasBeamGeometry()) {
    return detail::fail(error, "laserScanToMsg: the scan has no beam geometry (built from points), so its "
                               "beams are unknown; publish it as a PointCloud2");
  }
  sensor_msgs::LaserScan msg;
  msg.header = header;
  msg.angle_min = static_cast<float>(scan.angleMin());
  msg.angle_max = static_cast<float>(scan.angleMax());
  msg.angle_increment = static_cast<float>(scan.angleIncrement());
  msg.range_min = static_cast<float>(scan.rangeMin());
  msg.range_max = static_cast<float>(scan.rangeMax() > 0.0 ? scan.rangeMax() : std::numeric_limits<float>::max());
  msg.ranges = scan.toRanges();
  if (scan.hasIntensity()) {
    // Intensity of each beam: the beam a point belongs to is found from its bearing exactly as
    // toRanges() does, so ranges and intensities stay aligned.
    msg.intensities.assign(msg.ranges.size(), 0.0f);
    const int beams = static_cast<int>(msg.ranges.size());
    const double turn = 2.0 * M_PI / std::abs(scan.angleIncrement());
    const int cn = scan.data().channels();
    for (int i = 0; i < scan.size(); ++i) {
      const float* p = scan.data().ptr<float>(0) + static_cast<size_t>(i) * cn;
      double k = (std::atan2(p[1], p[0]) - scan.angleMin()) / scan.angleIncrement();
      while (k < -0.5) k += turn;
      while (k > beams - 0.5 + 1e-9 && k - turn >= -0.5) k -= turn;
      const long idx = std::lround(k);
      if (idx >= 0 && idx < beams) msg.intensities[static_cast<size_t>(idx)] = p[2];
    }
  }
  return msg;
}

}  // namespace rtabmap_conversions

#include "rtabmap_conversions/OdometryConversions.h"

#include <cmath>

#include "Support.h"
#include "rtabmap_conversions/TransformConversions.h"

namespace rtabmap_conversions {

boost::array<double, 36> covarianceToMsg(const Covariance6& covariance) {
  boost::array<double, 36> out;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) out[size_t(r * 6 + c)] = covariance(r, c);
  }
  return out;
}

Covariance6 covarianceFromMsg(const boost::array<double, 36>& values) {
  Covariance6 out;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) out(r, c) = values[size_t(r * 6 + c)];
  }
  return out;
}

nav_msgs::Odometry odometryToMsg(const rtabmap::Transform& pose, const Covariance6& covariance,
                                 const std_msgs::Header& header, const std::string& childFrameId) {
  nav_msgs::Odometry msg;
  msg.header = header;
  msg.child_frame_id = childFrameId;
  if (pose.isNull()) {
    msg.pose.pose = transformToPoseMsg(pose);  // all zeros, quaternion included
    msg.pose.covariance = covarianceToMsg(Covariance6::Identity() * kLostCovariance);
    msg.twist.covariance = msg.pose.covariance;
    return msg;
  }
  msg.pose.pose = transformToPoseMsg(pose);
  msg.pose.covariance = covarianceToMsg(covariance);
  return msg;
}

std::optional<OdometryReading> odometryFromMsg(const nav_msgs::Odometry& msg, std::string* error) {
  const std::string what = "Odometry of frame '" + msg.header.frame_id + "' -> '" + msg.child_frame_id + "'";
  if (msg.header.frame_id.empty()) return detail::fail(error, what + " has no frame_id");
  const auto& p = msg.pose.pose;
  const double poseValues[] = {p.position.x, p.position.y, p.position.z, p.orientation.x,
                               p.orientation.y, p.orientation.z, p.orientation.w};
  const auto& t = msg.twist.twist;
  const double twistValues[] = {t.linear.x, t.linear.y, t.linear.z, t.angular.x, t.angular.y, t.angular.z};
  if (!detail::allFinite(poseValues) || !detail::allFinite(twistValues) ||
      !detail::allFinite(msg.pose.covariance) || !detail::allFinite(msg.twist.covariance)) {
    return detail::fail(error, what + " has NaN or infinite values in its pose, twist or covariance");
  }
  OdometryReading out;
  out.stamp = msg.header.stamp.toSec();
  out.frameId = msg.header.frame_id;
  out.childFrameId = msg.child_frame_id;
  out.covariance = covarianceFromMsg(msg.pose.covariance);
  out.twistCovariance = covarianceFromMsg(msg.twist.covariance);
  for (int i = 0; i < 6; ++i) out.twist(i) = twistValues[i];
  // Only the x variance decides: planar wheel odometry legitimately puts huge variances on the
  // axes it does not observe (z, roll, pitch), which must not read as "lost".
  const bool lostCovariance = out.covariance(0, 0) >= kLostCovariance;
  out.pose = lostCovariance ? rtabmap::Transform() : transformFromPoseMsg(p);
  if (out.pose.isNull()) out.covariance = Covariance6::Identity() * kLostCovariance;
  return out;
}

}  // namespace rtabmap_conversions

#include "rtabmap_conversions/TransformConversions.h"

#include <cmath>

namespace rtabmap_conversions {

namespace {

// A zero quaternion is how a null Transform travels; anything else is normalised, so a
// message with a slightly denormalised quaternion (float round trips) is still accepted.
rtabmap::Transform fromParts(double x, double y, double z, double qx, double qy, double qz, double qw) {
  const double norm = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
  if (norm == 0.0 || !std::isfinite(norm) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
    return rtabmap::Transform();
  }
  return rtabmap::Transform(x, y, z, qx / norm, qy / norm, qz / norm, qw / norm);
}

}  // namespace

geometry_msgs::Transform transformToMsg(const rtabmap::Transform& transform) {
  geometry_msgs::Transform msg;
  if (transform.isNull()) {
    msg.rotation.w = 0.0;  // explicit: the all-zero message means "no transform"
    return msg;
  }
  const Eigen::Vector3d t = transform.translation();
  const Eigen::Quaterniond q = transform.quaternion();
  msg.translation.x = t.x();
  msg.translation.y = t.y();
  msg.translation.z = t.z();
  msg.rotation.x = q.x();
  msg.rotation.y = q.y();
  msg.rotation.z = q.z();
  msg.rotation.w = q.w();
  return msg;
}

rtabmap::Transform transformFromMsg(const geometry_msgs::Transform& msg) {
  return fromParts(msg.translation.x, msg.translation.y, msg.translation.z, msg.rotation.x,
                   msg.rotation.y, msg.rotation.z, msg.rotation.w);
}

geometry_msgs::Pose transformToPoseMsg(const rtabmap::Transform& transform) {
  const geometry_msgs::Transform t = transformToMsg(transform);
  geometry_msgs::Pose pose;
  pose.position.x = t.translation.x;
  pose.position.y = t.translation.y;
  pose.position.z = t.translation.z;
  pose.orientation = t.rotation;
  return pose;
}

rtabmap::Transform transformFromPoseMsg(const geometry_msgs::Pose& msg) {
  return fromParts(msg.position.x, msg.position.y, msg.position.z, msg.orientation.x,
                   msg.orientation.y, msg.orientation.z, msg.orientation.w);
}

}  // namespace rtabmap_conversions

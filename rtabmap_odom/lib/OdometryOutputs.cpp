#include "rtabmap_odom/OdometryOutputs.h"

#include <opencv2/core/mat.hpp>

#include <cmath>

namespace rtabmap_odom {

rtabmap::Transform guessFrameCorrection(const rtabmap::Transform& odomPose, const rtabmap::Transform& guessPose) {
  if (odomPose.isNull() || guessPose.isNull()) return rtabmap::Transform();
  return odomPose * guessPose.inverse();
}

Eigen::Matrix<double, 6, 1> twistFromMotion(const rtabmap::Transform& motion, double dt) {
  Eigen::Matrix<double, 6, 1> twist = Eigen::Matrix<double, 6, 1>::Zero();
  if (motion.isNull() || dt <= 0.0) return twist;
  double x, y, z, roll, pitch, yaw;
  motion.getTranslationAndEulerAngles(x, y, z, roll, pitch, yaw);
  twist << x / dt, y / dt, z / dt, roll / dt, pitch / dt, yaw / dt;
  return twist;
}

rtabmap::LaserScan pointsAsScan(const std::vector<cv::Point3f>& points) {
  cv::Mat data(1, int(points.size()), CV_32FC3);
  int n = 0;
  for (const cv::Point3f& p : points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    data.at<cv::Vec3f>(0, n++) = cv::Vec3f(p.x, p.y, p.z);
  }
  if (n == 0) return rtabmap::LaserScan();
  return rtabmap::LaserScan(data.colRange(0, n).clone(), n, 0.0, 0.0, rtabmap::LaserScan::kXYZ);
}

rtabmap::LaserScan scanInFrame(const rtabmap::LaserScan& scan, const rtabmap::Transform& pose) {
  if (scan.empty() || pose.isNull()) return rtabmap::LaserScan();
  const rtabmap::LaserScan placed(scan.data(), scan.maxPoints(), scan.rangeMin(), scan.rangeMax(), scan.format(),
                                  pose * scan.localTransform());
  return placed.transformedToBase();
}

bool UpdateRateLimiter::accept(double stamp) {
  if (rate_ <= 0.0) return true;
  // 1 % slack: a sensor at exactly the limit rate keeps every frame despite stamp jitter.
  if (last_ >= 0.0 && stamp >= last_ && stamp - last_ < 0.99 / rate_) return false;
  last_ = stamp;
  return true;
}

bool updateRateTooLow(int updates, double windowSeconds, double expectedRate) {
  if (expectedRate <= 0.0 || windowSeconds <= 0.0) return false;
  return updates < 0.8 * expectedRate * windowSeconds;
}

}  // namespace rtabmap_odom

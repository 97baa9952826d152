#include "rtabmap_core/sim/SensorRig.h"

#include <cmath>

namespace rtabmap::sim {

CameraSpec CameraSpec::standard(int width, int height, double baseline, double height_m) {
  CameraSpec c;
  c.intrinsics.width = width;
  c.intrinsics.height = height;
  c.intrinsics.fx = c.intrinsics.fy = 525.0 * width / 640.0;
  c.intrinsics.cx = 0.5 * (width - 1);
  c.intrinsics.cy = 0.5 * (height - 1);
  c.baseline = baseline;
  c.baseToOptical = Transform(0.12, 0.0, height_m, 0.0, 0.0, 0.0) * CameraModel::opticalRotation();
  return c;
}

CameraModel CameraSpec::rgbModel() const {
  CameraModel m(intrinsics.fx, intrinsics.fy, intrinsics.cx, intrinsics.cy, baseToOptical, 0.0,
                cv::Size(intrinsics.width, intrinsics.height));
  m.setName("rgb");
  return m;
}

CameraModel CameraSpec::leftModel() const {
  CameraModel m = rgbModel();
  m.setName("left");
  return m;
}

CameraModel CameraSpec::rightModel() const {
  CameraModel m(intrinsics.fx, intrinsics.fy, intrinsics.cx, intrinsics.cy, baseToRightOptical(),
                -intrinsics.fx * baseline, cv::Size(intrinsics.width, intrinsics.height));
  m.setName("right");
  return m;
}

StereoCameraModel CameraSpec::stereoModel() const {
  return StereoCameraModel("stereo", leftModel(), rightModel());
}

Transform CameraSpec::baseToRightOptical() const {
  // The right camera is `baseline` along the left optical frame's x axis.
  return baseToOptical * Transform(baseline, 0.0, 0.0, 0.0, 0.0, 0.0);
}

LaserSpec LaserSpec::urg04lx() {
  LaserSpec s;
  s.name = "urg";
  s.beams = 683;
  s.angleIncrement = 2.0 * M_PI / 1024.0;
  s.angleMin = -0.5 * (s.beams - 1) * s.angleIncrement;  // -119.88 deg .. +119.88 deg
  s.rangeMin = 0.02;
  s.rangeMax = 5.6;
  s.baseToLaser = Transform(0.15, 0.0, 0.25, 0.0, 0.0, 0.0);
  return s;
}

LaserSpec LaserSpec::utm30lx() {
  LaserSpec s;
  s.name = "utm";
  s.beams = 1081;
  s.angleIncrement = 0.25 * M_PI / 180.0;
  s.angleMin = -135.0 * M_PI / 180.0;
  s.rangeMin = 0.1;
  s.rangeMax = 30.0;
  s.baseToLaser = Transform(0.05, 0.0, 0.40, 0.0, 0.0, 0.0);
  return s;
}

LidarSpec LidarSpec::vlp16() { return LidarSpec(); }

}  // namespace rtabmap::sim

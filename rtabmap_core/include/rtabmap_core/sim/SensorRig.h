#pragma once
// The simulated robot's sensors and where they sit on it (REP-103 base frame: x forward, y
// left, z up, origin on the floor between the wheels).
//
//   camera  RGB-D + stereo, horizontal, optical centre 0.12 m ahead, 0.50 m up (the RGB camera
//           is the left camera of the stereo pair; the right one is `baseline` to its right)
//   urg     2D laser like a Hokuyo URG-04LX: 683 beams over 240 degrees (0.3516 deg steps,
//           360/1024), 0.02-5.6 m, 0.15 m ahead, 0.25 m up
//   utm     long-range 2D laser like a Hokuyo UTM-30LX: 1081 beams over 270 degrees (0.25 deg),
//           0.1-30 m, 0.05 m ahead, 0.40 m up
//   lidar   16-beam spinning lidar like a Velodyne VLP-16: +-15 deg in 2 deg steps, 0.2 deg
//           azimuth steps (1800 per turn), 0.5-100 m, on a mast 0.75 m up
//   imu     at (0, 0, 0.15), axes aligned with the base
#include <string>

#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/StereoCameraModel.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/sim/Renderer.h"

namespace rtabmap::sim {

struct CameraSpec {
  CameraIntrinsics intrinsics;
  Transform baseToOptical;  // base -> left (RGB) optical frame
  double baseline = 0.12;   // metres, right camera to the right of the left one

  // Pinhole intrinsics for a width x height image with the horizontal field of view of a
  // Kinect-class camera (fx = 525 at 640 px, about 62.8 deg), pixel centres at integers.
  static CameraSpec standard(int width = 640, int height = 480, double baseline = 0.12, double height_m = 0.5);

  CameraModel rgbModel() const;    // named "rgb"
  CameraModel leftModel() const;   // same intrinsics, named "left"
  CameraModel rightModel() const;  // Tx = -fx * baseline, named "right"
  StereoCameraModel stereoModel() const;  // named "stereo"
  // base -> right optical frame.
  Transform baseToRightOptical() const;
};

struct LaserSpec {
  std::string name;
  int beams = 0;
  double angleMin = 0.0;        // radians, first beam (counter-clockwise from x forward)
  double angleIncrement = 0.0;  // radians between beams
  double rangeMin = 0.0;
  double rangeMax = 0.0;
  Transform baseToLaser;        // horizontal mount: x, y, z and yaw only
  double noiseSigma = 0.0;      // range noise, metres (0: exact)

  double angleMax() const { return angleMin + angleIncrement * (beams - 1); }
  static LaserSpec urg04lx();
  static LaserSpec utm30lx();
};

struct LidarSpec {
  std::string name = "lidar";
  int rings = 16;
  double elevationMin = -15.0 * M_PI / 180.0;
  double elevationMax = 15.0 * M_PI / 180.0;
  int azimuthSteps = 1800;
  double rangeMin = 0.5;
  double rangeMax = 100.0;
  Transform baseToLidar = Transform(0.0, 0.0, 0.75, 0.0, 0.0, 0.0);
  double noiseSigma = 0.0;

  static LidarSpec vlp16();
};

}  // namespace rtabmap::sim

#pragma once
// Lidar scan-to-map odometry, S2M (JFR 2019, 3.2, Odom/Strategy 0 with Reg/Strategy 1): each
// new scan is registered by ICP against a point-cloud map of past key frames kept in the
// odometry frame. When the scan's correspondence ratio with the map falls under
// Odom/ScanKeyFrameThr (or the robot moved more than OdomF2M/ScanKeyFrameLinear /
// ScanKeyFrameAngular since the last key frame), the scan becomes a key frame: its points that
// are not already within OdomF2M/ScanSubtractRadius of the map (or whose normal differs by more
// than OdomF2M/ScanSubtractAngle) are added, and the oldest points are dropped beyond
// OdomF2M/ScanMaxSize (or beyond OdomF2M/ScanRange of the robot when that is set).
// Registering against a map rather than the last scan keeps the error from growing with every
// scan while the robot stays in the same area. Works for 2D scans and 3D clouds.
#include <memory>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/odometry/Odometry.h"

namespace rtabmap {

class OdometryS2M : public Odometry {
 public:
  // Throws ParameterError on an undeclared key or an invalid Icp/, Odom/ or OdomF2M/ value.
  explicit OdometryS2M(const ParametersMap& parameters = {});
  ~OdometryS2M() override;

  Type type() const override { return Type::kS2M; }

  // The local scan map in the odometry frame (XYNormal / XYZNormal when point-to-plane, else
  // XY / XYZ), for display and tests.
  LaserScan localMap() const;
  // Number of key frames added to the map since reset.
  int keyFrames() const;

 protected:
  Transform computeTransform(SensorData& data, const Transform& guess, OdometryInfo* info) override;
  void resetMap(const Transform& initialPose) override;
  bool needsInitialisation() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rtabmap

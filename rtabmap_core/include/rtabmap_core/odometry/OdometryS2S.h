#pragma once
// Lidar scan-to-scan odometry, S2S (JFR 2019, 3.2, Odom/Strategy 1 with Reg/Strategy 1): each
// new scan is registered by ICP against the last key frame scan, which is replaced by the new
// scan when their correspondence ratio falls under Odom/ScanKeyFrameThr (0 = every scan is a key
// frame). Cheaper than S2M and without a map to maintain, but the error of each key frame
// change accumulates. Works for 2D scans and 3D clouds.
#include <memory>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/odometry/Odometry.h"

namespace rtabmap {

class OdometryS2S : public Odometry {
 public:
  // Throws ParameterError on an undeclared key or an invalid Icp/ or Odom/ value.
  explicit OdometryS2S(const ParametersMap& parameters = {});
  ~OdometryS2S() override;

  Type type() const override { return Type::kS2S; }

  // The key frame scan, in its base frame, and its pose in the odometry frame (null before
  // the first scan).
  LaserScan keyFrameScan() const;
  Transform keyFramePose() const;
  // Number of key frames since reset.
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

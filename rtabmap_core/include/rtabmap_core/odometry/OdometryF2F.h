#pragma once
// Visual frame-to-frame odometry, F2F (JFR 2019, 3.1.1; Odom/Strategy 1 with images): each frame
// is registered against the last key frame only, by optical flow of the key frame's features
// (Vis/CorType 1, falling back to descriptor matching when the flow finds too few inliers) or
// by descriptor matching (Vis/CorType 0). The frame replaces the key frame when its inliers fall
// under Odom/KeyFrameThr of the key frame's features (or under Odom/VisKeyFrameThr). Cheaper
// than F2M, but each key frame change adds its error. RGB-D and stereo frames.
#include <memory>

#include "rtabmap_core/odometry/Odometry.h"

namespace rtabmap {

class OdometryF2F : public Odometry {
 public:
  // Throws ParameterError on an undeclared key or an invalid Vis/ or Odom/ value.
  explicit OdometryF2F(const ParametersMap& parameters = {});
  ~OdometryF2F() override;

  Type type() const override { return Type::kF2F; }

  // Pose of the key frame in the odometry frame (null before the first frame).
  Transform keyFramePose() const;
  int keyFramesAdded() const;

 protected:
  Transform computeTransform(SensorData& data, const Transform& guess, OdometryInfo* info) override;
  void resetMap(const Transform& initialPose) override;
  bool needsInitialisation() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rtabmap

#pragma once
// Visual frame-to-map odometry, F2M (JFR 2019, 3.1.1; Odom/Strategy 0 with images): each frame's
// features are registered (PnP RANSAC by default) against a local map of 3D features gathered
// from past key frames, in the odometry frame. The map holds at most OdomF2M/MaxSize features;
// when a frame's inliers fall under Odom/KeyFrameThr of the last key frame's features (or under
// Odom/VisKeyFrameThr), the frame becomes a key frame: its unmatched features with depth join the
// map (at most OdomF2M/MaxNewFeatures, strongest first), and the features not seen for the
// longest are dropped beyond the size limit. With OdomF2M/BundleAdjustment 3, each new key frame
// triggers a local bundle adjustment (Ceres) of the last OdomF2M/BundleAdjustmentMaxFrames key
// frames and the map points they see. Registering against a map rather than the last frame
// keeps drift from growing while the camera stays in a place. RGB-D and stereo frames.
#include <memory>
#include <vector>

#include <opencv2/core/types.hpp>

#include "rtabmap_core/odometry/Odometry.h"

namespace rtabmap {

class OdometryF2M : public Odometry {
 public:
  // Throws ParameterError on an undeclared key or an invalid Vis/, Odom/ or OdomF2M/ value.
  explicit OdometryF2M(const ParametersMap& parameters = {});
  ~OdometryF2M() override;

  Type type() const override { return Type::kF2M; }

  // The map's 3D features in the odometry frame (for display and tests).
  std::vector<cv::Point3f> localMapPoints() const;
  int localMapSize() const;
  // Key frames added since reset.
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

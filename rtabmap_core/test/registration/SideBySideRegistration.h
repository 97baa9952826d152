#pragma once
// Helpers of the tests that register frames of several cameras side by side (RGB-D:
// MultiCameraRegistration_test, stereo: MultiStereoRegistration_test).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <utility>

#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/registration/RegistrationVis.h"

namespace rtabmap::side_by_side_test {

struct Result {
  Transform transform;
  RegistrationInfo info;
  VisualCorrespondences details;
};

// Two prepared frames registered (the stereo options apply to stereo frames only).
inline Result registerFrames(const SensorData& a, const SensorData& b, const ParametersMap& parameters,
                             const Transform& guess = Transform()) {
  const RegistrationVis reg(parameters);
  const VisualFrame from = VisualFrame::fromSensorData(a, reg.detector().extract(a), reg.options().features.stereo);
  const VisualFrame to = VisualFrame::fromSensorData(b, reg.detector().extract(b), reg.options().features.stereo);
  Result r;
  r.transform = reg.computeTransform(from, to, guess, &r.info, &r.details);
  return r;
}

inline void expectNear(const Transform& actual, const Transform& expected, double metres, double radians) {
  ASSERT_FALSE(actual.isNull());
  const Transform e = expected.inverse() * actual;
  EXPECT_LT(e.translation().norm(), metres) << "error " << e.prettyPrint();
  EXPECT_LT(Eigen::AngleAxisd(e.toEigen().rotation()).angle(), radians) << "error " << e.prettyPrint();
}

// Inliers whose new-image position falls in camera 0 / camera 1.
inline std::pair<int, int> inliersPerCamera(const Result& r, int cameraWidth) {
  std::pair<int, int> n{0, 0};
  for (int k : r.details.inliers) {
    (r.details.toPoints[static_cast<size_t>(k)].x < cameraWidth ? n.first : n.second)++;
  }
  return n;
}

}  // namespace rtabmap::side_by_side_test

// Visual registration and odometry between frames of two stereo cameras looking in different
// directions (left images side by side, right images side by side): the known robot motion is
// recovered with inliers from both cameras, points3DAt uses the stereo pair of the camera under
// each point, and odometry (with image decimation too) follows the true path.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "MultiStereoScene.h"
#include "SideBySideRegistration.h"
#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/odometry/Odometry.h"
#include "rtabmap_core/registration/RegistrationVis.h"

using namespace rtabmap;
using namespace rtabmap::multistereo_test;
using namespace rtabmap::side_by_side_test;

TEST(MultiStereoRegistration, RecoversTheMotionWithBothCameras) {
  const test::SyntheticRoom room;
  const Transform poseA = basePose(0.2, -0.3, 0.1);
  const Transform poseB = basePose(0.3, -0.22, 0.15);
  const Transform expected = poseA.inverse() * poseB;
  const SensorData a = renderStereoFrame(room, poseA);
  const SensorData b = renderStereoFrame(room, poseB);
  const int w = a.imageRaw().cols / 2;
  const Transform guess = expected * Transform(0.03, -0.02, 0.0, 0.0, 0.0, 0.017);
  struct Case {
    std::string name;
    ParametersMap parameters;
    Transform guess;
  };
  const std::vector<Case> cases = {
      {"3D->3D, descriptors", {{"Vis/EstimationType", "0"}}, Transform()},
      {"multi-camera PnP, descriptors", {{"Vis/EstimationType", "1"}}, Transform()},
      {"multi-camera PnP, guided", {{"Vis/EstimationType", "1"}}, guess},
      {"multi-camera PnP, optical flow", {{"Vis/EstimationType", "1"}, {"Vis/CorType", "1"}}, guess},
      {"3D->3D, optical flow, no guess", {{"Vis/EstimationType", "0"}, {"Vis/CorType", "1"}}, Transform()},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Result r = registerFrames(a, b, c.parameters, c.guess);
    ASSERT_TRUE(r.info.success) << r.info.rejectedMsg;
    expectNear(r.transform, expected, 0.02, 0.01);
    const auto [cam0, cam1] = inliersPerCamera(r, w);
    EXPECT_GE(cam0, 20);
    EXPECT_GE(cam1, 20);
  }
}

TEST(MultiStereoRegistration, PointsAtUseTheStereoPairUnderEachPoint) {
  const test::SyntheticRoom room;
  const SensorData data = renderStereoFrame(room, basePose(0.2, -0.3, 0.1));
  const RegistrationVis reg;
  const ImageFeatures f = reg.detector().extract(data);
  const VisualFrame frame = VisualFrame::fromSensorData(data, f, reg.options().features.stereo);
  ASSERT_TRUE(frame.points3DAt);
  ASSERT_EQ(frame.models.size(), 2u);
  EXPECT_TRUE(frame.severalCameras());
  EXPECT_EQ(frame.cameraWidth(), data.imageRaw().cols / 2);
  EXPECT_EQ(frame.models[1].localTransform(), cameraLocal(1));
  // The same keypoints through points3DAt give the extraction's base-frame points.
  const std::vector<cv::Point3f> again = frame.points3DAt(f.keypoints);
  int compared = 0;
  for (size_t k = 0; k < again.size(); ++k) {
    if (!std::isfinite(again[k].x) || !std::isfinite(f.points3D[k].x)) continue;
    EXPECT_LT(cv::norm(again[k] - f.points3D[k]), 1e-4);
    ++compared;
  }
  EXPECT_GE(compared, f.validPoints3D() * 9 / 10);
}

// Frame-to-map and frame-to-frame odometry on two-stereo-camera frames, and with
// Odom/ImageDecimation 2 (every camera's model scaled, each sub-image shrunk on its own).
TEST(MultiStereoRegistration, VisualOdometryFollowsThePath) {
  const test::SyntheticRoom room;
  std::vector<Transform> path;
  for (int i = 0; i < 8; ++i) path.push_back(basePose(0.2 + 0.05 * i, -0.3 + 0.02 * i, 0.1 + 0.03 * i));
  struct Case {
    Odometry::Type type;
    ParametersMap parameters;
  };
  const std::vector<Case> cases = {{Odometry::Type::kF2M, {}},
                                   {Odometry::Type::kF2F, {}},
                                   {Odometry::Type::kF2M, {{"Odom/ImageDecimation", "2"}}}};
  for (const Case& c : cases) {
    SCOPED_TRACE(Odometry::typeName(c.type) + (c.parameters.empty() ? "" : " decimation 2"));
    const std::unique_ptr<Odometry> odom = Odometry::create(c.type, c.parameters);
    for (size_t i = 0; i < path.size(); ++i) {
      SensorData data = renderStereoFrame(room, path[i], 2, static_cast<int>(i) + 1, 1.0 + 0.1 * static_cast<double>(i));
      OdometryInfo info;
      const Transform pose = odom->process(data, &info);
      ASSERT_FALSE(pose.isNull()) << "frame " << i << ": " << info.lostReason;
      expectNear(pose, path.front().inverse() * path[i], 0.03, 0.015);
      // The features kept for the node are in the full-resolution combined image, both cameras.
      int second = 0;
      for (const cv::KeyPoint& k : data.keypoints()) second += k.pt.x >= data.imageRaw().cols / 2 ? 1 : 0;
      EXPECT_GT(second, 20) << "frame " << i;
      EXPECT_LT(second, static_cast<int>(data.keypoints().size()) - 20) << "frame " << i;
    }
  }
}

// Visual registration between two frames of two RGB-D cameras looking in different directions
// (issue 9, "several RGB-D"): the known robot motion is recovered by every correspondence and
// estimation strategy with inliers from both cameras, and where one camera alone sees a blank
// wall, the pair still registers.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "MultiCameraScene.h"
#include "SideBySideRegistration.h"
#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/odometry/Odometry.h"
#include "rtabmap_core/registration/RegistrationVis.h"

using namespace rtabmap;
using namespace rtabmap::multicam_test;
using namespace rtabmap::side_by_side_test;

TEST(MultiCameraRegistration, RecoversTheMotionWithEveryStrategyAndBothCameras) {
  const auto world = room(sim::MaterialKind::kMarble, sim::MaterialKind::kConcrete);
  const Transform poseA = basePose(2.0, 1.5, 0.1);
  const Transform poseB = basePose(2.12, 1.6, 0.16);
  const Transform expected = poseA.inverse() * poseB;
  const SensorData a = renderFrame(*world, poseA);
  const SensorData b = renderFrame(*world, poseB);
  const int w = intrinsics().width;
  // A guess off by 3 cm and 1 degree: guided matching projects into both cameras.
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
      {"3D->3D, guided", {{"Vis/EstimationType", "0"}}, guess},
      {"multi-camera PnP, optical flow", {{"Vis/EstimationType", "1"}, {"Vis/CorType", "1"}}, guess},
      {"3D->3D, optical flow, no guess", {{"Vis/EstimationType", "0"}, {"Vis/CorType", "1"}}, Transform()},
      // Two-view BA and the backward average are skipped with several cameras, not misapplied.
      {"PnP, BA and backward", {{"Vis/BundleAdjustment", "3"}, {"Vis/ForwardEstOnly", "false"}}, guess},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Result r = registerFrames(a, b, c.parameters, c.guess);
    ASSERT_TRUE(r.info.success) << r.info.rejectedMsg;
    expectNear(r.transform, expected, 0.01, 0.005);
    const auto [cam0, cam1] = inliersPerCamera(r, w);
    EXPECT_GE(cam0, 20);
    EXPECT_GE(cam1, 20);
  }
}

TEST(MultiCameraRegistration, PairRegistersWhereTheFirstCameraAloneSeesABlankWall) {
  // Camera 0 faces a plain painted wall (floor and ceiling plain too): alone it has nothing to
  // match; camera 1 sees the textured north wall.
  // 2.4 m from the walls, the 78-degree field of view of each camera stays on its own wall.
  const auto world = room(sim::MaterialKind::kPaint, sim::MaterialKind::kConcrete);
  const Transform poseA = basePose(3.5, 2.5, 0.0);
  const Transform poseB = basePose(3.6, 2.55, 0.05);
  const Transform expected = poseA.inverse() * poseB;
  for (const char* estimation : {"0", "1"}) {
    SCOPED_TRACE(std::string("Vis/EstimationType ") + estimation);
    const ParametersMap p = {{"Vis/EstimationType", estimation}};
    const Result alone = registerFrames(renderFrame(*world, poseA, 1), renderFrame(*world, poseB, 1), p);
    EXPECT_FALSE(alone.info.success) << "inliers " << alone.info.inliers;
    EXPECT_TRUE(alone.transform.isNull());
    const Result pair = registerFrames(renderFrame(*world, poseA), renderFrame(*world, poseB), p);
    ASSERT_TRUE(pair.info.success) << pair.info.rejectedMsg;
    expectNear(pair.transform, expected, 0.01, 0.005);
  }
}

TEST(MultiCameraRegistration, OpticalFlowKeepsEachTrackInItsCamera) {
  const auto world = room(sim::MaterialKind::kMarble, sim::MaterialKind::kConcrete);
  const Transform poseA = basePose(2.0, 1.5, 0.1);
  // A turn to the right moves camera 1's view towards camera 0's: tracks near camera 1's
  // left border would run over the seam.
  const Transform poseB = basePose(2.0, 1.5, 0.1 - 0.08);
  const RegistrationVis reg(ParametersMap{{"Vis/CorType", "1"}, {"Vis/EstimationType", "0"}});
  const SensorData a = renderFrame(*world, poseA);
  const SensorData b = renderFrame(*world, poseB);
  const VisualFrame from = VisualFrame::fromSensorData(a, reg.detector().extract(a));
  const VisualFrame to = VisualFrame::fromSensorData(b, reg.detector().extract(b));
  ASSERT_EQ(to.models.size(), 2u);
  RegistrationInfo info;
  VisualCorrespondences details;
  const Transform t = reg.computeTransform(from, to, Transform(), &info, &details);
  ASSERT_TRUE(info.success) << info.rejectedMsg;
  expectNear(t, poseA.inverse() * poseB, 0.01, 0.005);
  for (size_t k = 0; k < details.matches.size(); ++k) {
    const cv::KeyPoint& start = from.keypoints[static_cast<size_t>(details.matches[k].queryIdx)];
    EXPECT_EQ(from.cameraOf(start.pt.x), to.cameraOf(details.toPoints[k].x));
  }
}

TEST(MultiCameraRegistration, PointsAtUseTheCameraUnderEachPoint) {
  const auto world = room(sim::MaterialKind::kMarble, sim::MaterialKind::kConcrete);
  const SensorData data = renderFrame(*world, basePose(2.0, 1.5, 0.1));
  const RegistrationVis reg;
  const ImageFeatures f = reg.detector().extract(data);
  const VisualFrame frame = VisualFrame::fromSensorData(data, f);
  ASSERT_TRUE(frame.points3DAt);
  EXPECT_EQ(frame.cameraWidth(), intrinsics().width);
  // The same keypoints through points3DAt give the extraction's base-frame points.
  const std::vector<cv::Point3f> again = frame.points3DAt(f.keypoints);
  int compared = 0;
  for (size_t k = 0; k < again.size(); ++k) {
    if (!std::isfinite(again[k].x) || !std::isfinite(f.points3D[k].x)) continue;
    EXPECT_LT(cv::norm(again[k] - f.points3D[k]), 1e-4);
    ++compared;
  }
  EXPECT_GE(compared, static_cast<int>(f.size()) * 9 / 10);
}

// Visual odometry on two-camera frames: frame-to-map (with and without its local bundle
// adjustment, which is skipped for several cameras) and frame-to-frame follow the true path.
TEST(MultiCameraRegistration, VisualOdometryFollowsThePath) {
  const auto world = room(sim::MaterialKind::kMarble, sim::MaterialKind::kConcrete);
  std::vector<Transform> path;
  for (int i = 0; i < 8; ++i) path.push_back(basePose(2.0 + 0.08 * i, 1.5 + 0.02 * i, 0.1 + 0.03 * i));
  struct Case {
    Odometry::Type type;
    ParametersMap parameters;
  };
  const std::vector<Case> cases = {{Odometry::Type::kF2M, {}},
                                   {Odometry::Type::kF2M, {{"OdomF2M/BundleAdjustment", "3"}}},
                                   {Odometry::Type::kF2F, {}}};
  for (const Case& c : cases) {
    SCOPED_TRACE(Odometry::typeName(c.type) + (c.parameters.empty() ? "" : " with local BA"));
    const std::unique_ptr<Odometry> odom = Odometry::create(c.type, c.parameters);
    for (size_t i = 0; i < path.size(); ++i) {
      SensorData data = renderFrame(*world, path[i], 2, static_cast<int>(i) + 1, 1.0 + 0.1 * static_cast<double>(i));
      OdometryInfo info;
      const Transform pose = odom->process(data, &info);
      ASSERT_FALSE(pose.isNull()) << "frame " << i << ": " << info.lostReason;
      expectNear(pose, path.front().inverse() * path[i], 0.02, 0.01);
    }
  }
}

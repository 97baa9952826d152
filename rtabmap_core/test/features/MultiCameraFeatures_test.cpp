// Feature extraction from several RGB-D cameras side by side (issue 9, "several RGB-D"): each
// camera's sub-image gives keypoints offset into the combined image and 3D points in the base
// frame through its own model, checked against the room's known wall planes.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

#include "registration/MultiCameraScene.h"
#include "rtabmap_core/features/FeatureDetector.h"

using namespace rtabmap;
using namespace rtabmap::multicam_test;

namespace {

// Distance from a world point to the nearest wall plane of the room (the floor and ceiling are
// plain paint: no feature there).
double distanceToWalls(const Eigen::Vector3d& p) {
  return std::min(std::min(std::abs(p.x()), std::abs(p.x() - kRoomW)), std::min(std::abs(p.y()), std::abs(p.y() - kRoomD)));
}

struct PerCamera {
  int keypoints = 0;
  int with3D = 0;
  int onFacingWall = 0;   // camera 0 faces the east wall (x = W), camera 1 the north one (y = D)
  int onSomeWall = 0;
  int reprojected = 0;    // 3D point projects back through this camera onto its keypoint
};

std::vector<PerCamera> check(const ImageFeatures& f, const SensorData& data, const Transform& base) {
  std::vector<PerCamera> out(2);
  const int w = data.imageRaw().cols / 2;
  for (size_t k = 0; k < f.keypoints.size(); ++k) {
    const cv::KeyPoint& kp = f.keypoints[k];
    const int c = static_cast<int>(kp.pt.x) / w;
    PerCamera& s = out[static_cast<size_t>(c)];
    ++s.keypoints;
    const cv::Point3f& p = f.points3D[k];
    if (!std::isfinite(p.x)) continue;
    ++s.with3D;
    const Eigen::Vector3d world = base.toEigen() * Eigen::Vector3d(p.x, p.y, p.z);
    const double facing = c == 0 ? std::abs(world.x() - kRoomW) : std::abs(world.y() - kRoomD);
    s.onFacingWall += facing < 0.02 ? 1 : 0;
    s.onSomeWall += distanceToWalls(world) < 0.02 ? 1 : 0;
    const CameraModel& m = data.cameraModels()[static_cast<size_t>(c)];
    const Eigen::Vector3d q = m.localTransform().inverse().toEigen() * Eigen::Vector3d(p.x, p.y, p.z);
    const double u = m.fx() * q.x() / q.z() + m.cx() + c * w;
    const double v = m.fy() * q.y() / q.z() + m.cy();
    s.reprojected += std::hypot(u - kp.pt.x, v - kp.pt.y) < 0.5 ? 1 : 0;
  }
  return out;
}

}  // namespace

TEST(MultiCameraFeatures, EachCameraGivesBaseFramePointsOnTheWallItFaces) {
  const auto world = room(sim::MaterialKind::kMarble, sim::MaterialKind::kConcrete);
  const Transform base = basePose(2.0, 1.5, 0.1);
  const SensorData data = renderFrame(*world, base);
  FeatureOptions options;
  options.maxFeatures = 400;
  const FeatureDetector detector(options);
  FeatureExtractionInfo info;
  const ImageFeatures f = detector.extract(data, &info);
  ASSERT_TRUE(info.problem.empty()) << info.problem;
  ASSERT_EQ(f.points3D.size(), f.keypoints.size());
  ASSERT_EQ(f.descriptors.rows, static_cast<int>(f.keypoints.size()));
  const std::vector<PerCamera> s = check(f, data, base);
  for (int c = 0; c < 2; ++c) {
    SCOPED_TRACE("camera " + std::to_string(c));
    const PerCamera& p = s[static_cast<size_t>(c)];
    // Per camera max / N.
    EXPECT_LE(p.keypoints, 200);
    EXPECT_GE(p.keypoints, 100);
    EXPECT_GE(p.with3D, p.keypoints * 9 / 10);
    // Wrong local transform (or camera 0's applied to camera 1) would put them off the walls.
    EXPECT_EQ(p.onSomeWall, p.with3D);
    // The 78-degree field of view also catches the side walls near the corners.
    EXPECT_GE(p.onFacingWall, p.with3D * 2 / 3);
    EXPECT_EQ(p.reprojected, p.with3D);
  }
}

TEST(MultiCameraFeatures, NoLimitAndKpGroupKeepTheirMeaningPerCamera) {
  const auto world = room(sim::MaterialKind::kMarble, sim::MaterialKind::kConcrete);
  const SensorData data = renderFrame(*world, basePose(2.0, 1.5, 0.1));
  FeatureOptions none;
  none.maxFeatures = -1;  // Kp/MaxFeatures < 0: no words at all
  EXPECT_TRUE(FeatureDetector(none).extract(data).empty());
  FeatureOptions odd;
  odd.maxFeatures = 101;  // 50 each
  const std::vector<PerCamera> s = check(FeatureDetector(odd).extract(data), data, basePose(2.0, 1.5, 0.1));
  EXPECT_LE(s[0].keypoints, 50);
  EXPECT_LE(s[1].keypoints, 50);
  EXPECT_GE(s[0].keypoints, 25);
  EXPECT_GE(s[1].keypoints, 25);
}

TEST(MultiCameraFeatures, DepthMaskIsPerCamera) {
  const auto world = room(sim::MaterialKind::kMarble, sim::MaterialKind::kConcrete);
  SensorData data = renderFrame(*world, basePose(2.0, 1.5, 0.1));
  // Camera 1 sees nothing in range: it gives no feature, camera 0 still does.
  cv::Mat depth = data.depthOrRightRaw().clone();
  depth.colRange(depth.cols / 2, depth.cols).setTo(0.0f);
  const cv::Mat image = data.imageRaw().clone();
  const std::vector<CameraModel> models = data.cameraModels();
  data.setRGBDImage(image, depth, models);
  FeatureExtractionInfo info;
  const ImageFeatures f = FeatureDetector(FeatureOptions()).extract(data, &info);
  ASSERT_TRUE(info.problem.empty()) << info.problem;
  ASSERT_FALSE(f.empty());
  for (const cv::KeyPoint& k : f.keypoints) EXPECT_LT(k.pt.x, depth.cols / 2);
  // Both without depth: the frame is unusable, and says so.
  depth.setTo(0.0f);
  data.setRGBDImage(image, depth, models);
  FeatureDetector(FeatureOptions()).extract(data, &info);
  EXPECT_NE(info.problem.find("no valid pixel"), std::string::npos) << info.problem;
}

TEST(MultiCameraFeatures, InvalidModelOfOneCameraRefusesTheFrame) {
  const auto world = room(sim::MaterialKind::kMarble, sim::MaterialKind::kConcrete);
  const SensorData two = renderFrame(*world, basePose(2.0, 1.5, 0.1));
  std::vector<CameraModel> models = two.cameraModels();
  models[1] = CameraModel(0.0, 0.0, 80.0, 60.0, cameraLocal(1));
  FeatureExtractionInfo info;
  const ImageFeatures f = FeatureDetector(FeatureOptions()).extract(SensorData(two.imageRaw(), two.depthOrRightRaw(), models), &info);
  EXPECT_TRUE(f.empty());
  EXPECT_NE(info.problem.find("camera 1 model not valid"), std::string::npos) << info.problem;
}

// Feature extraction from several stereo cameras side by side (left images side by side, right
// images the same way, one StereoCameraModel each): each camera's keypoints are offset into the
// combined image, matched for disparity within its own right sub-image, and their 3D points land
// on the room's known faces in the base frame through that camera's own model.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

#include "registration/MultiStereoScene.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/features/FeatureDetector.h"

using namespace rtabmap;
using namespace rtabmap::multistereo_test;

namespace {

struct PerCamera {
  int keypoints = 0;
  int with3D = 0;
  int onRoom = 0;        // on a face of the room, within the stereo depth noise
  int reprojected = 0;   // 3D point projects back through this camera onto its keypoint
  int facing = 0;        // in front of this camera's optical axis direction on the robot
};

std::vector<PerCamera> check(const test::SyntheticRoom& room, const ImageFeatures& f, const SensorData& data,
                             const Transform& base) {
  const int n = static_cast<int>(data.stereoCameraModels().size());
  std::vector<PerCamera> out(static_cast<size_t>(n));
  const int w = data.imageRaw().cols / n;
  for (size_t k = 0; k < f.keypoints.size(); ++k) {
    const cv::KeyPoint& kp = f.keypoints[k];
    const int c = static_cast<int>(kp.pt.x) / w;
    PerCamera& s = out[static_cast<size_t>(c)];
    ++s.keypoints;
    const cv::Point3f& p = f.points3D[k];
    if (!std::isfinite(p.x)) continue;
    ++s.with3D;
    const Eigen::Vector3d inBase(p.x, p.y, p.z);
    const StereoCameraModel& m = data.stereoCameraModels()[static_cast<size_t>(c)];
    const Eigen::Vector3d q = m.localTransform().inverse().toEigen() * inBase;
    s.onRoom += distanceToRoom(room, base.toEigen() * inBase) < depthTolerance(q.z()) ? 1 : 0;
    const double u = m.left().fx() * q.x() / q.z() + m.left().cx() + c * w;
    const double v = m.left().fy() * q.y() / q.z() + m.left().cy();
    s.reprojected += q.z() > 0.0 && std::hypot(u - kp.pt.x, v - kp.pt.y) < 0.5 ? 1 : 0;
    const Eigen::Vector2d axis(std::cos(cameraYaw(c)), std::sin(cameraYaw(c)));
    s.facing += axis.dot(inBase.head<2>()) > 0.0 ? 1 : 0;
  }
  return out;
}

}  // namespace

TEST(MultiStereoFeatures, EachCameraGivesBaseFramePointsOnTheRoom) {
  const test::SyntheticRoom room;
  const Transform base = basePose(0.2, -0.3, 0.1);
  const SensorData data = renderStereoFrame(room, base);
  ASSERT_EQ(data.stereoCameraModels().size(), 2u);
  FeatureOptions options;
  options.maxFeatures = 400;
  FeatureExtractionInfo info;
  const ImageFeatures f = FeatureDetector(options).extract(data, &info);
  ASSERT_TRUE(info.problem.empty()) << info.problem;
  ASSERT_EQ(f.points3D.size(), f.keypoints.size());
  ASSERT_EQ(f.descriptors.rows, static_cast<int>(f.keypoints.size()));
  EXPECT_EQ(info.with3D, f.validPoints3D());
  const std::vector<PerCamera> s = check(room, f, data, base);
  for (int c = 0; c < 2; ++c) {
    SCOPED_TRACE("camera " + std::to_string(c));
    const PerCamera& p = s[static_cast<size_t>(c)];
    // Per camera max / N.
    EXPECT_LE(p.keypoints, 200);
    EXPECT_GE(p.keypoints, 100);
    EXPECT_GE(p.with3D, p.keypoints * 3 / 4);
    // Another camera's model or local transform would put them off the room and off their pixel.
    EXPECT_GE(p.onRoom, p.with3D * 95 / 100);
    EXPECT_EQ(p.reprojected, p.with3D);
    EXPECT_EQ(p.facing, p.with3D);
  }
}

TEST(MultiStereoFeatures, DisparitiesStayInTheCamerasOwnRightImage) {
  const test::SyntheticRoom room;
  const Transform base = basePose(0.2, -0.3, 0.1);
  const SensorData data = renderStereoFrame(room, base);
  // Camera 1's right image is blank: none of its keypoints can have a disparity. A trap for a
  // search that would cross the boundary: the last 128 columns of camera 0's right image hold
  // the combined left image 60 columns further right, so a keypoint of camera 1 within 60 px of
  // its left edge would find a perfect match there, 60 px of disparity away, in the other camera.
  cv::Mat right = data.depthOrRightRaw().clone();
  const int w = right.cols / 2;
  const int shift = 60;
  right.colRange(w, 2 * w).setTo(128);
  data.imageRaw().colRange(w - 128 + shift, w + shift).copyTo(right.colRange(w - 128, w));
  SensorData trapped = data;
  trapped.setStereoImage(data.imageRaw(), right, data.stereoCameraModels());
  for (bool opticalFlow : {true, false}) {
    SCOPED_TRACE(opticalFlow ? "optical flow" : "block matching");
    FeatureOptions options;
    options.stereo.opticalFlow = opticalFlow;
    FeatureExtractionInfo info;
    const ImageFeatures f = FeatureDetector(options).extract(trapped, &info);
    ASSERT_TRUE(info.problem.empty()) << info.problem;
    int camera0With3D = 0, camera1 = 0, camera1NearEdge = 0;
    for (size_t k = 0; k < f.keypoints.size(); ++k) {
      const float x = f.keypoints[k].pt.x;
      if (x < w) {
        camera0With3D += std::isfinite(f.points3D[k].x) ? 1 : 0;
        continue;
      }
      ++camera1;
      camera1NearEdge += x < w + shift ? 1 : 0;
      EXPECT_FALSE(std::isfinite(f.points3D[k].x)) << "camera 1 keypoint at " << f.keypoints[k].pt;
    }
    // Camera 1 still gives its keypoints (2D constraints for PnP), some in the trap's reach;
    // camera 0 is unaffected.
    EXPECT_GT(camera1, 100);
    EXPECT_GT(camera1NearEdge, 5);
    EXPECT_GT(camera0With3D, 100);
  }
}

TEST(MultiStereoFeatures, OneCameraAloneIsTheSingleStereoPath) {
  // Each camera of the pair, alone (its columns and its model as a single stereo frame), gives
  // the same features as in the pair (same per-camera budget): splitting changes nothing.
  const test::SyntheticRoom room;
  const SensorData two = renderStereoFrame(room, basePose(0.2, -0.3, 0.1));
  const int w = two.imageRaw().cols / 2;
  FeatureOptions pair;
  pair.maxFeatures = 400;
  FeatureOptions single;
  single.maxFeatures = 200;
  const ImageFeatures a = FeatureDetector(pair).extract(two);
  for (int c = 0; c < 2; ++c) {
    SCOPED_TRACE("camera " + std::to_string(c));
    const SensorData one(two.imageRaw().colRange(c * w, (c + 1) * w).clone(),
                         two.depthOrRightRaw().colRange(c * w, (c + 1) * w).clone(),
                         two.stereoCameraModels()[static_cast<size_t>(c)]);
    const ImageFeatures b = FeatureDetector(single).extract(one);
    std::vector<size_t> mine;
    for (size_t k = 0; k < a.keypoints.size(); ++k) {
      if (static_cast<int>(a.keypoints[k].pt.x) / w == c) mine.push_back(k);
    }
    ASSERT_EQ(mine.size(), b.keypoints.size());
    ASSERT_GT(b.validPoints3D(), 100);
    for (size_t i = 0; i < mine.size(); ++i) {
      EXPECT_EQ(a.keypoints[mine[i]].pt, b.keypoints[i].pt + cv::Point2f(static_cast<float>(c * w), 0.0f));
      const cv::Point3f& p = a.points3D[mine[i]];
      const cv::Point3f& q = b.points3D[i];
      EXPECT_EQ(std::isfinite(p.x), std::isfinite(q.x));
      if (std::isfinite(p.x) && std::isfinite(q.x)) {
        EXPECT_LT(cv::norm(p - q), 1e-5);
      }
      const cv::Mat da = a.descriptors.row(static_cast<int>(mine[i]));
      EXPECT_EQ(cv::norm(da, b.descriptors.row(static_cast<int>(i)), cv::NORM_HAMMING), 0);
    }
  }
}

TEST(MultiStereoFeatures, InconsistentInputIsRefusedWithAReason) {
  const test::SyntheticRoom room;
  const SensorData two = renderStereoFrame(room, basePose(0.2, -0.3, 0.1));
  std::vector<StereoCameraModel> models = two.stereoCameraModels();
  // An invalid model of one camera refuses the frame (a calibration error, not a blank view).
  models[1] = StereoCameraModel(200.0, 200.0, 160.0, 120.0, 0.0, cameraLocal(1));
  FeatureExtractionInfo info;
  const SensorData invalid(two.imageRaw(), two.depthOrRightRaw(), models);
  EXPECT_TRUE(FeatureDetector(FeatureOptions()).extract(invalid, &info).empty());
  EXPECT_NE(info.problem.find("stereo camera 1 model not valid"), std::string::npos) << info.problem;
  // Without the right images.
  FeatureDetector(FeatureOptions()).extract(SensorData(two.imageRaw(), cv::Mat(), two.stereoCameraModels()), &info);
  EXPECT_NE(info.problem.find("without its right image"), std::string::npos) << info.problem;
  // A width that does not split into the cameras, and left / right of different sizes.
  const std::vector<StereoCameraModel> three = {models[0], models[0], models[0]};
  EXPECT_THROW(SensorData(two.imageRaw(), two.depthOrRightRaw(), three), FormatError);
  EXPECT_THROW(SensorData(two.imageRaw(), two.depthOrRightRaw().colRange(0, 320).clone(), two.stereoCameraModels()),
               FormatError);
}

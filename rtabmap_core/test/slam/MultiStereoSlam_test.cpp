// SLAM with two stereo cameras side by side (left images side by side, right images the same
// way): Rtabmap::process() on a short out-and-back run in the synthetic room adds nodes that
// keep both stereo models and whose words come from both cameras with 3D on the room, and closes
// a loop whose transform matches the ground truth, although odometry drifted.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <map>
#include <optional>

#include "registration/MultiStereoScene.h"
#include "rtabmap_core/slam/Rtabmap.h"

using namespace rtabmap;
using namespace rtabmap::multistereo_test;

TEST(MultiStereoSlam, NodesKeepBothCamerasAndALoopCloses) {
  const test::SyntheticRoom room;
  std::vector<Transform> path;
  for (int i = 0; i <= 5; ++i) path.push_back(basePose(-1.0 + 0.3 * i, -0.3, 0.1));
  for (int i = 4; i >= 0; --i) path.push_back(basePose(-1.0 + 0.3 * i + 0.02, -0.28, 0.1 + 0.01));

  Rtabmap slam;
  slam.init({{"Rtabmap/DetectionRate", "0"},
             {"Mem/STMSize", "2"},
             // As MultiCameraSlam_test: in a small room the posterior spreads over every node;
             // each accepted loop is checked against the truth below.
             {"Rtabmap/LoopThr", "0.05"},
             {"RGBD/ProximityBySpace", "false"},
             {"Kp/MaxFeatures", "400"}},
            "");
  std::map<int, Transform> truth;
  int loops = 0;
  // Odometry drifts 1.5 cm a step and says so (3 cm standard deviation): the stereo loop
  // closures' covariance carries the depth noise of points 3 m away, so with the default 1 cm the
  // optimiser would keep the drift.
  const Eigen::Matrix<double, 6, 6> odomCovariance = Eigen::Matrix<double, 6, 6>::Identity() * 9e-4;
  for (size_t i = 0; i < path.size(); ++i) {
    // Odometry drifts: 5% of the distance travelled, along y.
    const double travelled = 0.3 * static_cast<double>(i);
    const Transform odom = path[i] * Transform(0.0, 0.05 * travelled, 0.0, 0.0, 0.0, 0.0);
    const SensorData data = renderStereoFrame(room, path[i], 2, static_cast<int>(i) + 1, 1.0 + static_cast<double>(i));
    ASSERT_TRUE(slam.process(data, odom, odomCovariance)) << "frame " << i << ": " << slam.lastRejection();
    const Statistics& s = slam.statistics();
    truth[s.refImageId] = path[i];
    if (s.loopClosureId <= 0) continue;
    ++loops;
    SCOPED_TRACE("loop " + std::to_string(s.refImageId) + " -> " + std::to_string(s.loopClosureId));
    ASSERT_TRUE(truth.count(s.loopClosureId));
    const Transform expected = truth[s.refImageId].inverse() * truth[s.loopClosureId];
    const Transform e = expected.inverse() * s.loopClosureTransform;
    EXPECT_LT(e.translation().norm(), 0.03) << s.loopClosureTransform.prettyPrint();
    EXPECT_LT(Eigen::AngleAxisd(e.toEigen().rotation()).angle(), 0.015);
  }
  EXPECT_GE(loops, 1);
  EXPECT_EQ(slam.summary().nodesAdded, static_cast<int>(path.size()));

  const int w = 320;
  for (const auto& [id, pose] : truth) {
    SCOPED_TRACE("node " + std::to_string(id));
    const std::optional<Signature> node = slam.node(id);
    ASSERT_TRUE(node.has_value());
    ASSERT_EQ(node->sensorData().stereoCameraModels().size(), 2u);
    EXPECT_EQ(node->sensorData().stereoCameraModels()[1].localTransform(), cameraLocal(1));
    // Without its images (what get_map_data's graph view asks), the node keeps both cameras.
    NodeDataParts noImages;
    noImages.images = false;
    const std::optional<Signature> light = slam.node(id, noImages);
    ASSERT_TRUE(light.has_value());
    EXPECT_TRUE(light->sensorData().imageCompressed().empty());
    EXPECT_TRUE(light->sensorData().imageRaw().empty());
    ASSERT_EQ(light->sensorData().stereoCameraModels().size(), 2u);
    EXPECT_EQ(light->sensorData().stereoCameraModels()[1].localTransform(), cameraLocal(1));
    int cam[2] = {0, 0};
    int onRoom = 0, with3D = 0;
    for (size_t k = 0; k < node->getWordsKpts().size(); ++k) {
      cam[node->getWordsKpts()[k].pt.x < w ? 0 : 1]++;
      const int c = node->getWordsKpts()[k].pt.x < w ? 0 : 1;
      const cv::Point3f& p = node->getWords3()[k];
      if (!std::isfinite(p.x)) continue;
      ++with3D;
      const Eigen::Vector3d inBase(p.x, p.y, p.z);
      const double depth = (cameraLocal(c).inverse().toEigen() * inBase).z();
      onRoom += distanceToRoom(room, pose.toEigen() * inBase) < depthTolerance(depth) ? 1 : 0;
    }
    EXPECT_GE(cam[0], 50);
    EXPECT_GE(cam[1], 50);
    EXPECT_GE(onRoom, with3D * 95 / 100);
  }
  // After the loop closures, the optimised poses are back near the truth (odometry drifted
  // by up to 0.075 m).
  const std::map<int, Transform> optimized = slam.optimizedPoses();
  const int last = slam.lastNodeId();
  ASSERT_TRUE(optimized.count(last));
  const Transform firstToLast = optimized.begin()->second.inverse() * optimized.at(last);
  const Transform truthFirstToLast = truth.begin()->second.inverse() * truth.at(last);
  EXPECT_LT((firstToLast.translation() - truthFirstToLast.translation()).norm(), 0.04);
}

// Reg/Strategy 2: visual registration refined by ICP on the nodes' scans.
#include <gtest/gtest.h>

#include "odometry/SyntheticRoom.h"
#include "registration/IcpTestScenes.h"
#include "rtabmap_core/memory/Signature.h"
#include "rtabmap_core/registration/IcpVisualRegistration.h"

namespace rtabmap {
namespace {

using test::SyntheticRoom;

// A node of the textured room seen by the RGB-D camera, with a planar lidar scan of the same
// room's walls (the room spans [-3, 3]^2).
SensorData roomNode(const SyntheticRoom& room, const Transform& pose, int id) {
  SensorData data = room.rgbd(pose, SyntheticRoom::camera(), id, id);
  test::World2D walls;
  test::addPolygon(walls, {-3, -3, 3, -3, 3, 3, -3, 3});
  data.setLaserScan(test::castScan2D(walls, pose.to3DoF(), {}));
  return data;
}

ParametersMap params() {
  return {{Parameters::kRegStrategy(), "2"},
          {Parameters::kIcpPointToPlane(), "true"},
          {Parameters::kIcpVoxelSize(), "0.02"},
          {Parameters::kIcpMaxCorrespondenceDistance(), "0.2"},
          {Parameters::kIcpIterations(), "30"}};
}

TEST(IcpVisualRegistration, VisualThenIcpReachesTheTruth) {
  const SyntheticRoom room;
  const Transform a(0.0, 0.0, 1.2, 0.0, 0.0, M_PI);
  const Transform b(-0.25, 0.1, 1.2, 0.0, 0.0, M_PI + 0.12);
  Signature from(roomNode(room, a, 1)), to(roomNode(room, b, 2));
  const IcpVisualRegistration registration(params());
  RegistrationInfo info;
  const Transform t = registration.computeTransform(from, to, Transform(), &info);
  ASSERT_FALSE(t.isNull()) << info.rejectedMsg;
  EXPECT_TRUE(info.success);
  const Transform truth = a.inverse() * b;
  EXPECT_LT(test::translationError(t, truth), 0.005);
  EXPECT_LT(test::rotationError(t, truth), 0.1 * M_PI / 180);
  // Both steps reported.
  EXPECT_GE(info.inliers, 20);
  EXPECT_GT(info.icpCorrespondences, 100);
  EXPECT_GT(info.icpInliersRatio, 0.8);
  EXPECT_LT(info.icpTranslation, 0.05);  // ICP only refined the visual result
  EXPECT_GT(info.covariance(0, 0), 0.0);
}

TEST(IcpVisualRegistration, FailsWithTheStepsReason) {
  const SyntheticRoom room;
  const Transform a(0.0, 0.0, 1.2, 0.0, 0.0, M_PI);
  const Transform b(-0.2, 0.0, 1.2, 0.0, 0.0, M_PI + 0.1);
  const IcpVisualRegistration registration(params());
  RegistrationInfo info;

  // No scan in the second node: the visual step succeeds, ICP cannot run.
  SensorData noScan = roomNode(room, b, 2);
  noScan.setLaserScan(LaserScan());
  Signature from(roomNode(room, a, 1)), bare(noScan);
  EXPECT_TRUE(registration.computeTransform(from, bare, Transform(), &info).isNull());
  EXPECT_EQ(info.rejectedMsg.rfind("ICP: ", 0), 0u) << info.rejectedMsg;
  EXPECT_NE(info.rejectedMsg.find("node 2 has none"), std::string::npos) << info.rejectedMsg;
  EXPECT_GE(info.inliers, 20);

  // A texture-less image: the visual step fails first.
  SensorData blank = roomNode(room, b, 3);
  blank.setRGBDImage(cv::Mat(blank.imageRaw().size(), blank.imageRaw().type(), cv::Scalar::all(128)),
                     blank.depthOrRightRaw(), blank.cameraModels());
  Signature flat(blank);
  EXPECT_TRUE(registration.computeTransform(from, flat, Transform(), &info).isNull());
  EXPECT_EQ(info.rejectedMsg.rfind("visual: ", 0), 0u) << info.rejectedMsg;
}

}  // namespace
}  // namespace rtabmap

#include "rtabmap_conversions/NodeDataConversions.h"

#include <gtest/gtest.h>

#include "TestHelpers.h"
#include "rtabmap_core/codec/Compression.h"

using namespace rtabmap_conversions;
using rtabmap::CameraModel;
using rtabmap::LaserScan;
using rtabmap::Link;
using rtabmap::SensorData;
using rtabmap::Signature;
using rtabmap::Transform;
using rtabmap_conversions::test::randomImage;
using rtabmap_conversions::test::sameBits;
using rtabmap_conversions::test::smoothImage;

namespace {

const Transform kCamera(0.1, 0.0, 0.5, -M_PI / 2, 0.0, -M_PI / 2);
const Transform kLaser(0.2, 0.0, 0.3, 0.0, 0.0, 0.0);

Signature richNode(int id) {
  SensorData data(smoothImage(48, 64, 3), randomImage(48, 64, CV_16UC1, unsigned(id)),
                  CameraModel(50.0, 51.0, 32.0, 24.0, kCamera, 0.0, cv::Size(64, 48)), id, 100.0 + id);
  std::vector<float> ranges(181, 3.0f);
  ranges[10] = std::numeric_limits<float>::infinity();
  data.setLaserScan(LaserScan::fromRanges(ranges, -M_PI / 2, M_PI / 180, 0.1, 30.0, kLaser));
  data.setUserData(randomImage(1, 20, CV_8UC1));
  rtabmap::LocalGrid grid;
  grid.ground = randomImage(1, 30, CV_32FC2);
  grid.obstacles = randomImage(1, 12, CV_32FC2);
  grid.empty = randomImage(1, 5, CV_32FC2);
  grid.cellSize = 0.05f;
  grid.viewPoint = Eigen::Vector3f(0.2f, 0.0f, 0.3f);
  data.setLocalGrid(grid);
  rtabmap::GPS gps;
  gps.stamp = 100.0 + id;
  gps.latitude = 45.4;
  gps.longitude = -71.9;
  gps.altitude = 250.0;
  gps.error = 3.0;
  gps.bearing = 90.0;
  data.setGPS(gps);
  Signature node(id, 2, 7, 100.0 + id, "kitchen", Transform(1.0 * id, 2.0, 0.0, 0.0, 0.0, 0.5),
                 Transform(1.0 * id, 2.1, 0.0, 0.0, 0.0, 0.45), data);
  std::multimap<int, int> words = {{11, 0}, {12, 1}, {11, 2}, {40, 3}};
  std::vector<cv::KeyPoint> kpts = {cv::KeyPoint(1, 2, 3), cv::KeyPoint(4, 5, 6), cv::KeyPoint(7, 8, 9),
                                    cv::KeyPoint(10, 11, 12)};
  std::vector<cv::Point3f> pts = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {10, 11, 12}};
  node.setWords(words, kpts, pts, randomImage(4, 32, CV_8UC1));
  return node;
}

}  // namespace

TEST(NodeDataConversions, NodeRoundTripsWithItsSensorDataWordsAndGrid) {
  const Signature node = richNode(3);
  const rtabmap_ros::NodeData msg = nodeDataToMsg(node);
  EXPECT_EQ(msg.id, 3);
  EXPECT_EQ(msg.label, "kitchen");
  EXPECT_FALSE(msg.image.empty());
  EXPECT_FALSE(msg.depth.empty());
  EXPECT_EQ(msg.laserScanMaxPts, 181);
  EXPECT_EQ(msg.laserScanFormat, int(LaserScan::kXY));
  ASSERT_EQ(msg.fx.size(), 1u);
  EXPECT_EQ(msg.wordIds, (std::vector<int>{11, 12, 11, 40}));

  std::string error;
  std::optional<Signature> back = nodeDataFromMsg(msg, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->id(), 3);
  EXPECT_EQ(back->mapId(), 2);
  EXPECT_EQ(back->weight(), 7);
  EXPECT_DOUBLE_EQ(back->stamp(), 103.0);
  EXPECT_EQ(back->label(), "kitchen");
  EXPECT_TRUE(back->getPose().toEigen().isApprox(node.getPose().toEigen(), 1e-12));
  EXPECT_TRUE(back->getGroundTruthPose().toEigen().isApprox(node.getGroundTruthPose().toEigen(), 1e-12));
  EXPECT_EQ(back->getWords(), node.getWords());
  EXPECT_EQ(back->getWords3()[3], node.getWords3()[3]);
  EXPECT_EQ(back->getWordsKpts()[2].pt, node.getWordsKpts()[2].pt);
  EXPECT_TRUE(sameBits(back->getWordsDescriptors(), node.getWordsDescriptors()));

  SensorData data = back->sensorData();
  EXPECT_DOUBLE_EQ(data.gps().latitude, 45.4);
  EXPECT_DOUBLE_EQ(data.gps().bearing, 90.0);
  ASSERT_EQ(data.cameraModels().size(), 1u);
  EXPECT_FLOAT_EQ(float(data.cameraModels()[0].fy()), 51.0f);
  EXPECT_EQ(data.cameraModels()[0].imageSize(), cv::Size(64, 48));
  EXPECT_TRUE(data.cameraModels()[0].localTransform().toEigen().isApprox(kCamera.toEigen(), 1e-12));
  data.uncompress();
  EXPECT_TRUE(sameBits(data.depthOrRightRaw(), node.sensorData().depthOrRightRaw()));  // png: lossless
  EXPECT_EQ(data.imageRaw().size(), cv::Size(64, 48));
  EXPECT_TRUE(sameBits(data.laserScanRaw().data(), node.sensorData().laserScanRaw().data()));
  EXPECT_EQ(data.laserScanRaw().maxPoints(), 181);
  EXPECT_DOUBLE_EQ(data.laserScanRaw().rangeMax(), 30.0);
  EXPECT_TRUE(data.laserScanRaw().localTransform().toEigen().isApprox(kLaser.toEigen(), 1e-12));
  EXPECT_TRUE(sameBits(data.userDataRaw(), node.sensorData().userDataRaw()));
  EXPECT_TRUE(sameBits(data.localGrid().obstacles, node.sensorData().localGrid().obstacles));
  EXPECT_EQ(data.localGrid().cellSize, 0.05f);
  EXPECT_EQ(data.localGrid().viewPoint, Eigen::Vector3f(0.2f, 0.0f, 0.3f));
}

TEST(NodeDataConversions, CompressedBytesArePassedThroughAndGraphViewOmitsThem) {
  Signature node = richNode(4);
  node.sensorData().compress(".png");
  const rtabmap::Bytes image = node.sensorData().imageCompressed();
  const rtabmap_ros::NodeData msg = nodeDataToMsg(node);
  EXPECT_EQ(msg.image, image);
  const rtabmap_ros::NodeData light = nodeDataToMsg(node, false);
  EXPECT_TRUE(light.image.empty());
  EXPECT_TRUE(light.laserScan.empty());
  EXPECT_TRUE(light.grid_ground.empty());
  EXPECT_EQ(light.wordIds.size(), 4u);
  EXPECT_EQ(light.fx.size(), 1u);
  ASSERT_TRUE(nodeDataFromMsg(light));
}

TEST(NodeDataConversions, StereoNodesKeepTheirBaseline) {
  SensorData data(smoothImage(48, 64, 1), randomImage(48, 64, CV_8UC1),
                  rtabmap::StereoCameraModel(60.0, 60.0, 32.0, 24.0, 0.25, kCamera, cv::Size(64, 48)), 9, 1.0);
  const rtabmap_ros::NodeData msg = nodeDataToMsg(Signature(9, 0, 0, 1.0, "", Transform::Identity(), Transform(), data));
  EXPECT_FLOAT_EQ(msg.baseline, 0.25f);
  const std::optional<Signature> back = nodeDataFromMsg(msg);
  ASSERT_TRUE(back);
  ASSERT_TRUE(back->sensorData().isStereo());
  EXPECT_NEAR(back->sensorData().stereoCameraModels()[0].baseline(), 0.25, 1e-6);
  SensorData raw = back->sensorData();
  raw.uncompress();
  EXPECT_TRUE(sameBits(raw.depthOrRightRaw(), data.depthOrRightRaw()));
}

TEST(NodeDataConversions, SeveralStereoCamerasTravelWithTheMessagesBaseline) {
  // Two stereo cameras side by side (left images, and right images, concatenated).
  const Transform second(0.0, 0.1, 0.5, -M_PI / 2, 0.0, 0.0);
  const std::vector<rtabmap::StereoCameraModel> models = {
      rtabmap::StereoCameraModel(60.0, 60.0, 32.0, 24.0, 0.25, kCamera, cv::Size(64, 48)),
      rtabmap::StereoCameraModel(62.0, 61.0, 31.0, 23.0, 0.25, second, cv::Size(64, 48))};
  SensorData data(smoothImage(48, 128, 1), randomImage(48, 128, CV_8UC1), models, 9, 1.0);
  const rtabmap_ros::NodeData msg = nodeDataToMsg(Signature(9, 0, 0, 1.0, "", Transform::Identity(), Transform(), data));
  ASSERT_EQ(msg.fx.size(), 2u);
  EXPECT_FLOAT_EQ(msg.baseline, 0.25f);
  std::string error;
  const std::optional<Signature> back = nodeDataFromMsg(msg, &error);
  ASSERT_TRUE(back) << error;
  const std::vector<rtabmap::StereoCameraModel>& got = back->sensorData().stereoCameraModels();
  ASSERT_EQ(got.size(), 2u);
  EXPECT_TRUE(back->sensorData().cameraModels().empty());
  for (size_t i = 0; i < 2; ++i) {
    SCOPED_TRACE("camera " + std::to_string(i));
    EXPECT_NEAR(got[i].baseline(), 0.25, 1e-6);
    EXPECT_NEAR(got[i].left().fx(), models[i].left().fx(), 1e-4);
    EXPECT_NEAR(got[i].left().fy(), models[i].left().fy(), 1e-4);
    EXPECT_NEAR(got[i].left().cx(), models[i].left().cx(), 1e-4);
    EXPECT_EQ(got[i].left().imageSize(), cv::Size(64, 48));
    EXPECT_LT(got[i].localTransform().getDistance(models[i].localTransform()), 1e-6);
    EXPECT_LT((got[i].localTransform().inverse() * models[i].localTransform()).getAngle(), 1e-6);
  }
  SensorData raw = back->sensorData();
  raw.uncompress();
  EXPECT_TRUE(sameBits(raw.depthOrRightRaw(), data.depthOrRightRaw()));
  // MapData carries them the same way.
  const rtabmap_ros::MapData map = mapDataToMsg({{9, Transform::Identity()}}, {}, {{9, *back}}, Transform::Identity(),
                                                std_msgs::Header());
  ASSERT_EQ(map.nodes.size(), 1u);
  EXPECT_EQ(map.nodes[0].fx.size(), 2u);
  EXPECT_FLOAT_EQ(map.nodes[0].baseline, 0.25f);
}

TEST(NodeDataConversions, BadNodesAreErrors) {
  std::string error;
  const rtabmap_ros::NodeData good = nodeDataToMsg(richNode(5));
  auto expectError = [&](const rtabmap_ros::NodeData& msg, const std::string& words) {
    error.clear();
    EXPECT_FALSE(nodeDataFromMsg(msg, &error)) << words;
    EXPECT_NE(error.find(words), std::string::npos) << error;
    EXPECT_NE(error.find("node 5"), std::string::npos) << error;
  };
  rtabmap_ros::NodeData m = good;
  m.cy.clear();
  expectError(m, "camera arrays");
  m = good;
  m.laserScanFormat = 77;
  expectError(m, "scan format");
  m = good;
  m.grid_obstacles.resize(m.grid_obstacles.size() - 3);
  expectError(m, "grid_obstacles");
  m = good;
  m.wordKpts.pop_back();
  expectError(m, "word ids");
  m = good;
  m.wordIds.pop_back();
  m.wordKpts.pop_back();
  m.wordPts.pop_back();
  expectError(m, "descriptors");
}

TEST(NodeDataConversions, MapDataPutsLinksBackOnTheirNodes) {
  std::map<int, Signature> nodes = {{1, richNode(1)}, {2, richNode(2)}};
  std::map<int, Transform> poses = {{1, Transform::Identity()}, {2, Transform(1, 0, 0)}};
  std::multimap<int, Link> links;
  links.emplace(1, Link(1, 2, Link::kNeighbor, Transform(1, 0, 0)));
  links.emplace(2, Link(2, 1, Link::kNeighbor, Transform(-1, 0, 0)));
  links.emplace(2, Link(2, 7, Link::kGlobalClosure, Transform(3, 0, 0)));  // to a node not sent
  std_msgs::Header header;
  header.frame_id = "map";
  const rtabmap_ros::MapData msg = mapDataToMsg(poses, links, nodes, Transform(0.5, 0, 0), header);
  EXPECT_EQ(msg.nodes.size(), 2u);
  std::string error;
  const std::optional<MapData> back = mapDataFromMsg(msg, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->graph.poses.size(), 2u);
  EXPECT_EQ(back->graph.links.size(), 3u);
  ASSERT_EQ(back->nodes.size(), 2u);
  EXPECT_TRUE(back->nodes.at(1).hasLink(2, Link::kNeighbor));
  EXPECT_TRUE(back->nodes.at(2).hasLink(7, Link::kGlobalClosure));
  EXPECT_EQ(back->nodes.at(2).label(), "kitchen");

  rtabmap_ros::MapData bad = msg;
  bad.nodes[1].laserScanFormat = -3;
  EXPECT_FALSE(mapDataFromMsg(bad, &error));
  EXPECT_NE(error.find("node 2"), std::string::npos) << error;
}

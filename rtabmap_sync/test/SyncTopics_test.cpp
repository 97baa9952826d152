// Topic selection from the subscribe_* parameters, and the 5-second warning text.
#include <gtest/gtest.h>

#include "rtabmap_sync/SyncTopics.h"

namespace rtabmap_sync {
namespace {

std::vector<std::string> names(const std::vector<TopicSlot>& slots) {
  std::vector<std::string> out;
  for (const TopicSlot& s : slots) out.push_back(s.topic);
  return out;
}

TEST(SyncTopics, DepthModeSubscribesTheClassicRgbdTopics) {
  SubscribeOptions o;
  o.subscribeDepth = true;
  const std::vector<TopicSlot> slots = selectTopics(o);
  EXPECT_EQ(names(slots), (std::vector<std::string>{"rgb/image", "depth/image", "rgb/camera_info"}));
  EXPECT_STREQ(messageType(slots[1].kind), "sensor_msgs/Image");
  EXPECT_STREQ(messageType(slots[2].kind), "sensor_msgs/CameraInfo");
  // subscribe_rgb with subscribe_depth is one mode (depth implies the rgb image).
  o.subscribeRgb = true;
  EXPECT_EQ(names(selectTopics(o)), names(slots));
}

TEST(SyncTopics, RgbOnlyIsMonocular) {
  SubscribeOptions o;
  o.subscribeRgb = true;
  EXPECT_EQ(names(selectTopics(o)), (std::vector<std::string>{"rgb/image", "rgb/camera_info"}));
}

TEST(SyncTopics, RgbdCamerasNameTheTopics) {
  SubscribeOptions o;
  o.subscribeRgbd = true;
  o.rgbdCameras = 1;
  EXPECT_EQ(names(selectTopics(o)), (std::vector<std::string>{"rgbd_image"}));
  o.rgbdCameras = 3;
  const std::vector<TopicSlot> three = selectTopics(o);
  EXPECT_EQ(names(three), (std::vector<std::string>{"rgbd_image0", "rgbd_image1", "rgbd_image2"}));
  EXPECT_EQ(three[2].camera, 2);
  EXPECT_STREQ(messageType(three[0].kind), "rtabmap_ros/RGBDImage");
  o.rgbdCameras = 0;
  const std::vector<TopicSlot> bundled = selectTopics(o);
  EXPECT_EQ(names(bundled), (std::vector<std::string>{"rgbd_images"}));
  EXPECT_STREQ(messageType(bundled[0].kind), "rtabmap_ros/RGBDImages");
}

TEST(SyncTopics, EveryInputInFixedOrder) {
  SubscribeOptions o;
  o.subscribeStereo = true;
  o.subscribeScanCloud = true;
  o.subscribeOdom = true;
  o.subscribeOdomInfo = true;
  o.subscribeUserData = true;
  EXPECT_EQ(names(selectTopics(o)),
            (std::vector<std::string>{"left/image_rect", "right/image_rect", "left/camera_info", "right/camera_info",
                                      "scan_cloud", "odom", "odom_info", "user_data"}));
  o.subscribeStereo = false;
  o.subscribeScanCloud = false;
  o.subscribeScan = true;
  const std::vector<TopicSlot> slots = selectTopics(o);
  EXPECT_EQ(names(slots), (std::vector<std::string>{"scan", "odom", "odom_info", "user_data"}));
  EXPECT_STREQ(messageType(slots[0].kind), "sensor_msgs/LaserScan");
  EXPECT_STREQ(messageType(slots[1].kind), "nav_msgs/Odometry");
}

TEST(SyncTopics, ConflictsAreErrorsNamingTheParameters) {
  std::string error;
  SubscribeOptions o;
  o.subscribeStereo = true;
  o.subscribeDepth = true;
  EXPECT_TRUE(selectTopics(o, &error).empty());
  EXPECT_NE(error.find("subscribe_stereo"), std::string::npos) << error;
  EXPECT_NE(error.find("subscribe_depth"), std::string::npos) << error;

  o = SubscribeOptions();
  o.subscribeScan = true;
  o.subscribeScanCloud = true;
  EXPECT_TRUE(selectTopics(o, &error).empty());
  EXPECT_NE(error.find("subscribe_scan_cloud"), std::string::npos) << error;

  EXPECT_TRUE(selectTopics(SubscribeOptions(), &error).empty());
  EXPECT_NE(error.find("no input"), std::string::npos) << error;

  o = SubscribeOptions();
  o.subscribeRgbd = true;
  o.rgbdCameras = -1;
  EXPECT_TRUE(selectTopics(o, &error).empty());
  EXPECT_NE(error.find("rgbd_cameras"), std::string::npos) << error;
}

TEST(SyncTopics, AtMostNineTopics) {
  SubscribeOptions o;
  o.subscribeRgbd = true;
  o.rgbdCameras = 8;
  o.subscribeScan = true;
  EXPECT_EQ(selectTopics(o).size(), 9u);
  o.subscribeOdom = true;
  std::string error;
  EXPECT_TRUE(selectTopics(o, &error).empty());
  EXPECT_NE(error.find("10 topics"), std::string::npos) << error;
}

TEST(SyncTopics, PolicyDescription) {
  SubscribeOptions o;
  o.approxSync = true;
  o.queueSize = 10;
  o.approxSyncMaxInterval = 0.02;
  EXPECT_EQ(describePolicy(o), "approx sync, queue 10, max interval 0.020 s");
  o.approxSyncMaxInterval = 0.0;
  EXPECT_EQ(describePolicy(o), "approx sync, queue 10");
  o.approxSync = false;
  o.queueSize = 5;
  o.approxSyncMaxInterval = 0.02;  // meaningless for exact sync: not shown
  EXPECT_EQ(describePolicy(o), "exact sync, queue 5");
}

TEST(SyncTopics, WarningListsEachTopicWhatArrivedAndThePolicy) {
  const std::vector<TopicStatus> topics = {{"/cam/rgb/image", "sensor_msgs/Image", 12, 12, 100.5},
                                           {"/cam/depth/image", "sensor_msgs/Image", 0, 0, 0.0},
                                           {"/cam/rgb/camera_info", "sensor_msgs/CameraInfo", 12, 12, 100.5}};
  const std::string text = noDataWarning("/rgbd_sync", 5, topics, "approx sync, queue 10");
  EXPECT_EQ(text.rfind("/rgbd_sync: did not receive data since 5 seconds!", 0), 0u) << text;
  EXPECT_NE(text.find("(approx sync, queue 10)"), std::string::npos) << text;
  EXPECT_NE(text.find("\n   /cam/rgb/image [sensor_msgs/Image]: 12 received, last stamp 100.500000"),
            std::string::npos) << text;
  EXPECT_NE(text.find("\n   /cam/depth/image [sensor_msgs/Image]: nothing received"), std::string::npos) << text;
  EXPECT_NE(text.find("\n   /cam/rgb/camera_info [sensor_msgs/CameraInfo]: 12 received"), std::string::npos) << text;
  EXPECT_NE(text.find("Make sure every topic above is published"), std::string::npos) << text;
  EXPECT_EQ(text.find("too far apart"), std::string::npos) << text;
}

TEST(SyncTopics, WarningBlamesStampsWhenEveryTopicArrives) {
  const std::vector<TopicStatus> topics = {{"/a", "sensor_msgs/Image", 3, 9, 1.0}, {"/b", "sensor_msgs/Image", 4, 9, 9.0}};
  const std::string text = noDataWarning("/n", 5, topics, "exact sync, queue 10");
  EXPECT_EQ(text.find("nothing received"), std::string::npos) << text;
  EXPECT_EQ(text.find("stopped"), std::string::npos) << text;
  EXPECT_NE(text.find("too far apart for the sync policy"), std::string::npos) << text;
}

// A sensor that went silent mid-run (issue 10's dropouts) is told apart from a topic never
// published: its line says it stopped and when (its last stamp), and the hint is not "remap it".
TEST(SyncTopics, WarningShowsWhenATopicStopped) {
  const std::vector<TopicStatus> topics = {{"/cam/rgb/image", "sensor_msgs/Image", 9, 310, 155.5},
                                           {"/scan", "sensor_msgs/LaserScan", 0, 290, 150.5}};
  const std::string text = noDataWarning("/rtabmap", 5, topics, "exact sync, queue 10");
  EXPECT_NE(text.find("\n   /cam/rgb/image [sensor_msgs/Image]: 9 received, last stamp 155.500000"), std::string::npos)
      << text;
  EXPECT_NE(text.find("\n   /scan [sensor_msgs/LaserScan]: stopped, nothing since the last synchronised set, last "
                      "stamp 150.500000 (290 received in all)"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("nothing received"), std::string::npos) << text;
  EXPECT_EQ(text.find("Make sure every topic above is published"), std::string::npos) << text;
  EXPECT_NE(text.find("A topic above stopped"), std::string::npos) << text;
  EXPECT_EQ(text.find("too far apart"), std::string::npos) << text;
}

TEST(SyncTopics, ImageTransportsPickTheCompressedTopics) {
  SubscribeOptions o;
  o.subscribeDepth = true;
  o.subscribeScan = true;
  std::vector<TopicSlot> raw = selectTopics(o);
  for (const TopicSlot& s : raw) EXPECT_FALSE(s.compressed()) << s.topic;

  // "compressed" reads the colour image as jpeg/png and the depth as compressedDepth.
  o.imageTransport = "compressed";
  std::vector<TopicSlot> slots = selectTopics(o);
  ASSERT_EQ(slots.size(), 4u);
  EXPECT_EQ(slots[0].transport, "compressed");
  EXPECT_EQ(slots[1].transport, "compressedDepth");
  EXPECT_FALSE(slots[2].compressed());  // camera_info
  EXPECT_FALSE(slots[3].compressed());  // scan
  EXPECT_STREQ(messageType(slots[0]), "sensor_msgs/CompressedImage");
  EXPECT_STREQ(messageType(slots[2]), "sensor_msgs/CameraInfo");
  // The suffix follows the resolved (remapped) base name, as image_transport does.
  EXPECT_EQ(transportTopic(slots[0], "/camera/rgb/image_rect_color"), "/camera/rgb/image_rect_color/compressed");
  EXPECT_EQ(transportTopic(slots[1], "/camera/depth/image"), "/camera/depth/image/compressedDepth");
  EXPECT_EQ(transportTopic(slots[2], "/camera/rgb/camera_info"), "/camera/rgb/camera_info");

  // The depth transport on its own; stereo images follow image_transport.
  o.imageTransport = "raw";
  o.depthImageTransport = "compressedDepth";
  slots = selectTopics(o);
  EXPECT_FALSE(slots[0].compressed());
  EXPECT_EQ(slots[1].transport, "compressedDepth");
  SubscribeOptions stereo;
  stereo.subscribeStereo = true;
  stereo.imageTransport = "compressed";
  slots = selectTopics(stereo);
  EXPECT_EQ(slots[0].transport, "compressed");
  EXPECT_EQ(slots[1].transport, "compressed");
}

TEST(SyncTopics, UnknownImageTransportIsAnErrorNamingIt) {
  SubscribeOptions o;
  o.subscribeDepth = true;
  o.imageTransport = "theora";
  std::string error;
  EXPECT_TRUE(selectTopics(o, &error).empty());
  EXPECT_NE(error.find("image_transport \"theora\""), std::string::npos) << error;
  o.imageTransport = "raw";
  o.depthImageTransport = "png";
  EXPECT_TRUE(selectTopics(o, &error).empty());
  EXPECT_NE(error.find("depth_image_transport \"png\""), std::string::npos) << error;
}

}  // namespace
}  // namespace rtabmap_sync

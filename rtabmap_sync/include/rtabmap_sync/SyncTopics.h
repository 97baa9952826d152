#pragma once
// Which topics a node synchronises, from the classic subscribe_* parameters, and the text of
// the "did not receive data" warning. ROS-free, so both are unit-tested without a master.
//
// Camera inputs (one mode at a time):
//   subscribe_rgbd    rgbd_cameras = 1: rgbd_image; N > 1: rgbd_image0 .. rgbd_image<N-1>;
//                     0: rgbd_images (one rtabmap_ros/RGBDImages holding every camera)
//   subscribe_stereo  left/image_rect, right/image_rect, left/camera_info, right/camera_info
//   subscribe_depth   rgb/image, depth/image, rgb/camera_info
//   subscribe_rgb     rgb/image, rgb/camera_info (monocular)
// Other inputs: subscribe_scan -> scan, subscribe_scan_cloud -> scan_cloud (not both),
// subscribe_odom -> odom, subscribe_odom_info -> odom_info, subscribe_user_data -> user_data.
//
// Image transports, as image_transport names them (Debian ships no transport plugins, so the
// compressed ones are decoded here): image_transport "raw" (default), "compressed" or
// "compressedDepth" for the rgb / left / right images; depth_image_transport for the depth
// image, which follows image_transport by default ("compressed" becomes "compressedDepth", the
// only lossless depth transport). A compressed image is read from <resolved topic>/<transport>
// as a sensor_msgs/CompressedImage.
#include <string>
#include <vector>

namespace rtabmap_sync {

enum class TopicKind {
  kRgbImage, kDepthImage, kRgbCameraInfo,
  kLeftImage, kRightImage, kLeftCameraInfo, kRightCameraInfo,
  kRgbdImage, kRgbdImages,
  kScan, kScanCloud, kOdom, kOdomInfo, kUserData
};

// The ROS message type of a kind, e.g. "sensor_msgs/Image".
const char* messageType(TopicKind kind);

struct SubscribeOptions {
  bool subscribeDepth = false;
  bool subscribeRgb = false;
  bool subscribeRgbd = false;
  bool subscribeStereo = false;
  bool subscribeScan = false;
  bool subscribeScanCloud = false;
  bool subscribeOdom = false;
  bool subscribeOdomInfo = false;
  bool subscribeUserData = false;
  int rgbdCameras = 1;
  // Sync policy: message_filters ApproximateTime (approx) or ExactTime.
  bool approxSync = true;
  int queueSize = 10;
  double approxSyncMaxInterval = 0.0;  // seconds; 0 = no limit on a set's stamp spread
  std::string imageTransport = "raw";      // image_transport
  std::string depthImageTransport;         // depth_image_transport; empty: from imageTransport
};

struct TopicSlot {
  TopicKind kind;
  std::string topic;  // relative to the node's namespace, as the classic nodes name them
  int camera = 0;     // index of the RGB-D camera for kRgbdImage
  std::string transport = "raw";  // images: raw, compressed or compressedDepth
  bool compressed() const { return transport != "raw"; }
};

// The ROS message type of a slot: a compressed image is a sensor_msgs/CompressedImage.
const char* messageType(const TopicSlot& slot);
// The topic a slot is read from, given its resolved name: <resolved>/<transport> when compressed.
std::string transportTopic(const TopicSlot& slot, const std::string& resolved);

// message_filters synchronises at most this many topics.
constexpr int kMaxSyncedTopics = 9;

// The topics in a fixed order (camera, scan, odom, odom_info, user_data). An empty vector and
// *error when the options conflict (two camera modes, scan and scan_cloud, rgbd_cameras < 0,
// more than kMaxSyncedTopics topics, an unknown image transport) or ask for nothing.
std::vector<TopicSlot> selectTopics(const SubscribeOptions& options, std::string* error = nullptr);

// "approx sync, queue 10, max interval 0.020 s" / "exact sync, queue 10".
std::string describePolicy(const SubscribeOptions& options);

// What arrived on one subscribed topic since the last synchronised set, and since the start.
struct TopicStatus {
  std::string topic;  // resolved name
  std::string type;
  int received = 0;        // since the last synchronised set
  long receivedEver = 0;   // since the node started
  double lastStamp = 0.0;  // header stamp of the last one (seconds); meaningful if receivedEver > 0
};

// The warning a node logs when no synchronised set came out for `seconds`: the node, each
// subscribed topic with its type and what arrived, the sync policy, and the likely cause
// (a topic never published or not remapped, a topic that stopped, or stamps too far apart for
// the policy). A topic that stopped shows its last stamp: the moment the sensor went silent.
std::string noDataWarning(const std::string& node, double seconds, const std::vector<TopicStatus>& topics,
                          const std::string& policy);

}  // namespace rtabmap_sync

#include "rtabmap_sync/SyncTopics.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace rtabmap_sync {

namespace {

bool fail(std::string* error, const std::string& why) {
  if (error) *error = why;
  return false;
}

// At most one camera mode: subscribe_depth implies the rgb image, so rgb + depth is one mode.
bool checkCameraModes(const SubscribeOptions& o, std::string* error) {
  std::vector<std::string> modes;
  if (o.subscribeRgbd) modes.push_back("subscribe_rgbd");
  if (o.subscribeStereo) modes.push_back("subscribe_stereo");
  if (o.subscribeDepth) modes.push_back("subscribe_depth");
  else if (o.subscribeRgb) modes.push_back("subscribe_rgb");
  if (modes.size() > 1) {
    std::string list;
    for (const std::string& m : modes) list += (list.empty() ? "" : ", ") + m;
    return fail(error, "only one camera input can be set, but " + list + " are true");
  }
  if (o.subscribeScan && o.subscribeScanCloud) {
    return fail(error, "subscribe_scan and subscribe_scan_cloud are both true; choose one");
  }
  if (o.subscribeRgbd && o.rgbdCameras < 0) {
    return fail(error, "rgbd_cameras must be >= 0 (got " + std::to_string(o.rgbdCameras) + ")");
  }
  return true;
}

void addCameraTopics(const SubscribeOptions& o, std::vector<TopicSlot>& slots) {
  if (o.subscribeRgbd) {
    if (o.rgbdCameras == 0) {
      slots.push_back({TopicKind::kRgbdImages, "rgbd_images"});
    } else if (o.rgbdCameras == 1) {
      slots.push_back({TopicKind::kRgbdImage, "rgbd_image"});
    } else {
      for (int i = 0; i < o.rgbdCameras; ++i) {
        slots.push_back({TopicKind::kRgbdImage, "rgbd_image" + std::to_string(i), i});
      }
    }
  } else if (o.subscribeStereo) {
    slots.push_back({TopicKind::kLeftImage, "left/image_rect"});
    slots.push_back({TopicKind::kRightImage, "right/image_rect"});
    slots.push_back({TopicKind::kLeftCameraInfo, "left/camera_info"});
    slots.push_back({TopicKind::kRightCameraInfo, "right/camera_info"});
  } else if (o.subscribeDepth || o.subscribeRgb) {
    slots.push_back({TopicKind::kRgbImage, "rgb/image"});
    if (o.subscribeDepth) slots.push_back({TopicKind::kDepthImage, "depth/image"});
    slots.push_back({TopicKind::kRgbCameraInfo, "rgb/camera_info"});
  }
}

bool isImage(TopicKind k) {
  return k == TopicKind::kRgbImage || k == TopicKind::kDepthImage || k == TopicKind::kLeftImage ||
         k == TopicKind::kRightImage;
}

// The transport of each image slot; false and *error for a name image_transport does not know.
bool setTransports(const SubscribeOptions& o, std::vector<TopicSlot>& slots, std::string* error) {
  const auto known = [](const std::string& t) { return t == "raw" || t == "compressed" || t == "compressedDepth"; };
  std::string depth = o.depthImageTransport;
  if (depth.empty()) depth = o.imageTransport == "compressed" ? "compressedDepth" : o.imageTransport;
  for (const auto& [name, value] : {std::make_pair("image_transport", o.imageTransport),
                                    std::make_pair("depth_image_transport", depth)}) {
    if (!known(value)) {
      return fail(error, std::string(name) + " \"" + value + "\" is not a transport this node reads (raw, compressed, compressedDepth)");
    }
  }
  for (TopicSlot& s : slots) {
    if (isImage(s.kind)) s.transport = s.kind == TopicKind::kDepthImage ? depth : o.imageTransport;
  }
  return true;
}

}  // namespace

const char* messageType(const TopicSlot& slot) {
  return slot.compressed() ? "sensor_msgs/CompressedImage" : messageType(slot.kind);
}

std::string transportTopic(const TopicSlot& slot, const std::string& resolved) {
  return slot.compressed() ? resolved + "/" + slot.transport : resolved;
}

const char* messageType(TopicKind kind) {
  switch (kind) {
    case TopicKind::kRgbImage:
    case TopicKind::kDepthImage:
    case TopicKind::kLeftImage:
    case TopicKind::kRightImage: return "sensor_msgs/Image";
    case TopicKind::kRgbCameraInfo:
    case TopicKind::kLeftCameraInfo:
    case TopicKind::kRightCameraInfo: return "sensor_msgs/CameraInfo";
    case TopicKind::kRgbdImage: return "rtabmap_ros/RGBDImage";
    case TopicKind::kRgbdImages: return "rtabmap_ros/RGBDImages";
    case TopicKind::kScan: return "sensor_msgs/LaserScan";
    case TopicKind::kScanCloud: return "sensor_msgs/PointCloud2";
    case TopicKind::kOdom: return "nav_msgs/Odometry";
    case TopicKind::kOdomInfo: return "rtabmap_ros/OdomInfo";
    case TopicKind::kUserData: return "rtabmap_ros/UserData";
  }
  return "?";
}

std::vector<TopicSlot> selectTopics(const SubscribeOptions& o, std::string* error) {
  if (!checkCameraModes(o, error)) return {};
  std::vector<TopicSlot> slots;
  addCameraTopics(o, slots);
  if (o.subscribeScan) slots.push_back({TopicKind::kScan, "scan"});
  if (o.subscribeScanCloud) slots.push_back({TopicKind::kScanCloud, "scan_cloud"});
  if (o.subscribeOdom) slots.push_back({TopicKind::kOdom, "odom"});
  if (o.subscribeOdomInfo) slots.push_back({TopicKind::kOdomInfo, "odom_info"});
  if (o.subscribeUserData) slots.push_back({TopicKind::kUserData, "user_data"});
  if (!setTransports(o, slots, error)) return {};
  if (slots.empty()) {
    fail(error, "no input: set one of subscribe_depth, subscribe_rgb, subscribe_rgbd, subscribe_stereo, "
                "subscribe_scan, subscribe_scan_cloud, subscribe_odom");
    return {};
  }
  if (static_cast<int>(slots.size()) > kMaxSyncedTopics) {
    fail(error, std::to_string(slots.size()) + " topics to synchronise, but message_filters handles at most " +
                    std::to_string(kMaxSyncedTopics) + " (fewer rgbd_cameras, or merge cameras with rgbdx_sync)");
    return {};
  }
  return slots;
}

std::string describePolicy(const SubscribeOptions& o) {
  std::ostringstream s;
  s << (o.approxSync ? "approx" : "exact") << " sync, queue " << o.queueSize;
  if (o.approxSync && o.approxSyncMaxInterval > 0.0) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.3f", o.approxSyncMaxInterval);
    s << ", max interval " << buf << " s";
  }
  return s.str();
}

std::string noDataWarning(const std::string& node, double seconds, const std::vector<TopicStatus>& topics,
                          const std::string& policy) {
  std::ostringstream s;
  s << node << ": did not receive data since " << seconds << " seconds! Subscribed to (" << policy << "):";
  bool anyNever = false, anyStopped = false;
  for (const TopicStatus& t : topics) {
    s << "\n   " << t.topic << " [" << t.type << "]: ";
    char stamp[48];
    std::snprintf(stamp, sizeof(stamp), "%.6f", t.lastStamp);
    if (t.receivedEver == 0) {
      s << "nothing received";
      anyNever = true;
    } else if (t.received == 0) {
      s << "stopped, nothing since the last synchronised set, last stamp " << stamp << " (" << t.receivedEver
        << " received in all)";
      anyStopped = true;
    } else {
      s << t.received << " received, last stamp " << stamp;
    }
  }
  if (anyNever) {
    s << "\nMake sure every topic above is published (\"rostopic hz <topic>\") and remapped to this node.";
  } else if (anyStopped) {
    s << "\nA topic above stopped (its sensor or driver went silent: \"rostopic hz <topic>\"); "
         "updates resume when it comes back.";
  } else {
    s << "\nEvery topic is published: their header stamps are too far apart for the sync policy "
         "(use approx_sync, a larger approx_sync_max_interval or queue_size, or check the stamps).";
  }
  return s.str();
}

}  // namespace rtabmap_sync

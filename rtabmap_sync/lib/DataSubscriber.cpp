#include "rtabmap_sync/DataSubscriber.h"

#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>

#include <mutex>
#include <optional>
#include <sstream>
#include <utility>

#include "ErasedSync.h"
#include "rtabmap_conversions/CompressedImageConversions.h"
#include "rtabmap_conversions/ImageConversions.h"
#include "rtabmap_sync/DropCounter.h"
#include "rtabmap_sync/LogThrottle.h"

namespace rtabmap_sync {

SubscribeOptions readSubscribeOptions(const ros::NodeHandle& pnh, const SubscribeOptions& d) {
  SubscribeOptions o = d;
  pnh.param("subscribe_depth", o.subscribeDepth, d.subscribeDepth);
  pnh.param("subscribe_rgb", o.subscribeRgb, d.subscribeRgb);
  pnh.param("subscribe_rgbd", o.subscribeRgbd, d.subscribeRgbd);
  pnh.param("subscribe_stereo", o.subscribeStereo, d.subscribeStereo);
  pnh.param("subscribe_scan", o.subscribeScan, d.subscribeScan);
  pnh.param("subscribe_scan_cloud", o.subscribeScanCloud, d.subscribeScanCloud);
  pnh.param("subscribe_odom", o.subscribeOdom, d.subscribeOdom);
  pnh.param("subscribe_odom_info", o.subscribeOdomInfo, d.subscribeOdomInfo);
  pnh.param("subscribe_user_data", o.subscribeUserData, d.subscribeUserData);
  pnh.param("rgbd_cameras", o.rgbdCameras, d.rgbdCameras);
  pnh.param("approx_sync", o.approxSync, d.approxSync);
  pnh.param("approx_sync_max_interval", o.approxSyncMaxInterval, d.approxSyncMaxInterval);
  pnh.param("queue_size", o.queueSize, d.queueSize);
  pnh.param("image_transport", o.imageTransport, d.imageTransport);
  pnh.param("depth_image_transport", o.depthImageTransport, d.depthImageTransport);
  return o;
}

namespace {

// How long without a synchronised set before the warning, as the classic nodes do.
constexpr double kWarnAfterSeconds = 5.0;

template <class M>
boost::shared_ptr<M const> as(const detail::ErasedPtr& e) {
  return boost::static_pointer_cast<M const>(e->message);
}

void assign(SyncedData& d, const TopicSlot& slot, const detail::ErasedPtr& e) {
  switch (slot.kind) {
    case TopicKind::kRgbImage: d.rgb = as<sensor_msgs::Image>(e); break;
    case TopicKind::kDepthImage: d.depth = as<sensor_msgs::Image>(e); break;
    case TopicKind::kRgbCameraInfo: d.rgbCameraInfo = as<sensor_msgs::CameraInfo>(e); break;
    case TopicKind::kLeftImage: d.left = as<sensor_msgs::Image>(e); break;
    case TopicKind::kRightImage: d.right = as<sensor_msgs::Image>(e); break;
    case TopicKind::kLeftCameraInfo: d.leftCameraInfo = as<sensor_msgs::CameraInfo>(e); break;
    case TopicKind::kRightCameraInfo: d.rightCameraInfo = as<sensor_msgs::CameraInfo>(e); break;
    case TopicKind::kRgbdImage: d.rgbdImages.push_back(as<rtabmap_ros::RGBDImage>(e)); break;
    case TopicKind::kRgbdImages: d.rgbdImagesMsg = as<rtabmap_ros::RGBDImages>(e); break;
    case TopicKind::kScan: d.scan = as<sensor_msgs::LaserScan>(e); break;
    case TopicKind::kScanCloud: d.scanCloud = as<sensor_msgs::PointCloud2>(e); break;
    case TopicKind::kOdom: d.odom = as<nav_msgs::Odometry>(e); break;
    case TopicKind::kOdomInfo: d.odomInfo = as<rtabmap_ros::OdomInfo>(e); break;
    case TopicKind::kUserData: d.userData = as<rtabmap_ros::UserData>(e); break;
  }
}

// A compressed / compressedDepth image as the sensor_msgs/Image the raw transport would carry.
std::optional<sensor_msgs::Image> decodeCompressed(const sensor_msgs::CompressedImage& m, bool depth, std::string* why) {
  std::optional<cv::Mat> mat = rtabmap_conversions::compressedImageFromMsg(m, why);
  if (!mat) return std::nullopt;
  if (depth && mat->type() != CV_16UC1 && mat->type() != CV_32FC1) {
    *why = "a depth image must decode to 16UC1 or 32FC1 (got " + std::to_string(mat->channels()) + " channel(s))";
    return std::nullopt;
  }
  try {
    return rtabmap_conversions::imageToMsg(*mat, m.header);
  } catch (const std::exception& e) {  // a decoded type ROS images cannot carry
    *why = e.what();
    return std::nullopt;
  }
}

}  // namespace

struct DataSubscriber::Impl {
  std::string name;
  SubscribeOptions options;
  std::vector<TopicSlot> slots;
  std::vector<ros::Subscriber> subscribers;
  std::unique_ptr<detail::ErasedSync> sync;  // null with a single topic: nothing to pair
  Callback callback;
  ros::WallTimer watch;

  mutable std::mutex mutex;  // guards the fields below (topic callbacks vs the watch timer)
  std::vector<TopicStatus> status;
  std::vector<ros::Time> lastStamps;
  ros::Time lastClock;  // ROS time when a message was last accepted
  ros::WallTime lastDelivery;
  ros::WallTime lastWarning;
  long delivered = 0;
  long dropped = 0;
  LogThrottle errors;
  DropCounter drops;
  long dropsWarned = 0;  // drops.dropped() at the last warning
  long clockJumps = 0;   // ROS time seen going back (SyncedData::clockJumps)

  // Stop the callbacks before the synchroniser and the node's callback go away.
  ~Impl() {
    watch.stop();
    for (ros::Subscriber& s : subscribers) s.shutdown();
  }

  template <class M>
  void subscribe(ros::NodeHandle& nh, int slot) {
    boost::function<void(const boost::shared_ptr<M const>&)> cb = [this, slot](const boost::shared_ptr<M const>& m) {
      onMessage(slot, m->header.stamp, m);
    };
    subscribers.push_back(nh.subscribe<M>(slots[size_t(slot)].topic, uint32_t(options.queueSize), cb));
  }

  // A compressed image decoded to the sensor_msgs/Image the synchroniser pairs; one that does
  // not decode is dropped with a (throttled) error naming the topic.
  void subscribeCompressed(ros::NodeHandle& nh, int slot, const std::string& topic) {
    const bool depth = slots[size_t(slot)].kind == TopicKind::kDepthImage;
    boost::function<void(const sensor_msgs::CompressedImageConstPtr&)> cb =
        [this, slot, topic, depth](const sensor_msgs::CompressedImageConstPtr& m) {
          std::string why;
          std::optional<sensor_msgs::Image> image = decodeCompressed(*m, depth, &why);
          if (!image) {
            std::lock_guard<std::mutex> lock(mutex);
            ++dropped;
            if (errors.due(topic + " decode")) {
              ROS_ERROR("%s: %s: cannot decode the image (format \"%s\"): %s; message dropped.", name.c_str(),
                        topic.c_str(), m->format.c_str(), why.c_str());
            }
            return;
          }
          onMessage(slot, m->header.stamp, boost::make_shared<const sensor_msgs::Image>(std::move(*image)));
        };
    subscribers.push_back(nh.subscribe<sensor_msgs::CompressedImage>(topic, uint32_t(options.queueSize), cb));
  }

  void subscribeSlot(ros::NodeHandle& nh, int i) {
    const TopicSlot& slot = slots[size_t(i)];
    if (slot.compressed()) {
      subscribeCompressed(nh, i, status[size_t(i)].topic);
      return;
    }
    switch (slot.kind) {
      case TopicKind::kRgbImage:
      case TopicKind::kDepthImage:
      case TopicKind::kLeftImage:
      case TopicKind::kRightImage: subscribe<sensor_msgs::Image>(nh, i); break;
      case TopicKind::kRgbCameraInfo:
      case TopicKind::kLeftCameraInfo:
      case TopicKind::kRightCameraInfo: subscribe<sensor_msgs::CameraInfo>(nh, i); break;
      case TopicKind::kRgbdImage: subscribe<rtabmap_ros::RGBDImage>(nh, i); break;
      case TopicKind::kRgbdImages: subscribe<rtabmap_ros::RGBDImages>(nh, i); break;
      case TopicKind::kScan: subscribe<sensor_msgs::LaserScan>(nh, i); break;
      case TopicKind::kScanCloud: subscribe<sensor_msgs::PointCloud2>(nh, i); break;
      case TopicKind::kOdom: subscribe<nav_msgs::Odometry>(nh, i); break;
      case TopicKind::kOdomInfo: subscribe<rtabmap_ros::OdomInfo>(nh, i); break;
      case TopicKind::kUserData: subscribe<rtabmap_ros::UserData>(nh, i); break;
    }
  }

  // ROS time (simulated with use_sim_time) is earlier than when the last message was accepted.
  bool clockWentBack() const {
    const ros::Time now = ros::Time::now();
    return !lastClock.isZero() && !now.isZero() && now < lastClock;
  }

  // Unset or non-increasing stamps are dropped here: ApproximateTime assumes each topic's
  // stamps increase, and a duplicated frame would be paired twice.
  bool acceptStamp(int slot, const ros::Time& stamp) {
    const std::string& topic = status[size_t(slot)].topic;
    if (stamp.isZero()) {
      ++dropped;
      if (errors.due(topic + " zero")) {
        ROS_ERROR("%s: %s has no header stamp (0); message dropped. Set the stamps.", name.c_str(), topic.c_str());
      }
      return false;
    }
    ros::Time& last = lastStamps[size_t(slot)];
    if (!last.isZero() && stamp <= last && clockWentBack()) {
      // A restarted bag (rosbag play --clock again) or a simulator reset: ROS time itself went
      // back, so the older stamps are the new normal. Start over, as tf2's listener does; the
      // SLAM core starts a new map when odometry restarts at the origin.
      ROS_WARN("%s: ROS time jumped back to %.6f (%s stamp %.6f after %.6f): a restarted bag? Accepting the new "
               "stamps from now on.", name.c_str(), ros::Time::now().toSec(), topic.c_str(), stamp.toSec(),
               last.toSec());
      for (ros::Time& t : lastStamps) t = ros::Time();
      drops.resetStamps();
      ++clockJumps;
    }
    if (!last.isZero() && stamp <= last) {
      ++dropped;
      const char* what = stamp == last ? "duplicated" : "out of order";
      if (errors.due(topic + what)) {
        ROS_ERROR("%s: %s stamp %.6f is not after the previous one %.6f (%s); message dropped.", name.c_str(),
                  topic.c_str(), stamp.toSec(), last.toSec(), what);
      }
      return false;
    }
    last = stamp;
    lastClock = ros::Time::now();
    TopicStatus& s = status[size_t(slot)];
    ++s.received;
    ++s.receivedEver;
    s.lastStamp = stamp.toSec();
    drops.received(size_t(slot), stamp.toSec());
    return true;
  }

  void onMessage(int slot, const ros::Time& stamp, const boost::shared_ptr<void const>& message) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (!acceptStamp(slot, stamp)) return;
    }
    auto erased = boost::make_shared<detail::ErasedMsg>();
    erased->stamp = stamp;
    erased->message = message;
    if (sync) {
      sync->add(slot, erased);  // calls deliver() when a set is complete
    } else {
      deliver({erased});
    }
  }

  void deliver(const std::vector<detail::ErasedPtr>& set) {
    SyncedData data;
    for (size_t i = 0; i < set.size() && i < slots.size(); ++i) assign(data, slots[i], set[i]);
    data.stamp = set.front()->stamp;
    std::string lost;
    {
      std::lock_guard<std::mutex> lock(mutex);
      ++delivered;
      data.clockJumps = clockJumps;
      lastDelivery = ros::WallTime::now();
      for (TopicStatus& s : status) s.received = 0;
      std::vector<double> stamps;
      for (const detail::ErasedPtr& m : set) stamps.push_back(m->stamp.toSec());
      drops.delivered(stamps);
      if (drops.dropped() > dropsWarned && errors.due("input lost")) {
        dropsWarned = drops.dropped();
        lost = lostText();
      }
    }
    if (!lost.empty()) ROS_WARN_STREAM(lost);
    callback(data);
  }

  // What was lost so far, per topic (the mutex held).
  std::string lostText() const {
    std::ostringstream o;
    o << name << ": input lost, about " << drops.setsLost() << " set(s) of " << (delivered + drops.setsLost())
      << " since the start:";
    for (size_t i = 0; i < status.size(); ++i) {
      if (drops.missingFromStamps(i) == 0 && drops.droppedInSync(i) == 0) continue;
      o << "\n   " << status[i].topic << ": " << drops.missingFromStamps(i) << " missing from its stamps (every "
        << drops.typicalInterval(i) << " s), " << drops.droppedInSync(i) << " received but never paired";
    }
    o << "\n Missing stamps: roscpp dropped them while the node was busy (queue_size " << options.queueSize
      << ": raise it, or lower the input rate / the node's work per update), or the sensor skipped them. "
         "Never paired: the synchroniser (" << describePolicy(options) << ") got no partners for them in time.";
    return o.str();
  }

  std::string warningText(double seconds) const {
    std::lock_guard<std::mutex> lock(mutex);
    return noDataWarning(name, seconds, status, describePolicy(options));
  }

  void onWatch(const ros::WallTimerEvent&) {
    const ros::WallTime now = ros::WallTime::now();
    {
      std::lock_guard<std::mutex> lock(mutex);
      if ((now - lastDelivery).toSec() < kWarnAfterSeconds || (now - lastWarning).toSec() < kWarnAfterSeconds) return;
      lastWarning = now;
    }
    ROS_WARN_STREAM(warningText(kWarnAfterSeconds));
  }
};

DataSubscriber::DataSubscriber() : impl_(std::make_unique<Impl>()) {}
DataSubscriber::~DataSubscriber() = default;

bool DataSubscriber::setup(ros::NodeHandle& nh, const std::string& name, const SubscribeOptions& options,
                           const Callback& callback, std::string* error) {
  std::string why;
  std::vector<TopicSlot> slots = selectTopics(options, &why);
  if (slots.empty()) {
    if (error) *error = name + ": " + why;
    return false;
  }
  options_ = options;
  if (options_.queueSize < 1) {
    ROS_ERROR("%s: queue_size must be >= 1 (got %d), using 10.", name.c_str(), options_.queueSize);
    options_.queueSize = 10;
  }
  Impl& d = *impl_;
  d.name = name;
  d.options = options_;
  d.slots = slots;
  d.callback = callback;
  d.lastStamps.assign(slots.size(), ros::Time());
  // The policies keep at most queue_size messages (sets) waiting; a few more is slack.
  // ApproximateTime leaves out the extra messages of a faster topic by design: not drops.
  d.drops = DropCounter(slots.size(), size_t(options_.queueSize) + 2, !options_.approxSync);
  d.lastDelivery = ros::WallTime::now();
  for (const TopicSlot& s : slots) {
    // Remappings apply to the base name ("rgb/image"), the transport's suffix comes after, as
    // image_transport does.
    d.status.push_back({transportTopic(s, nh.resolveName(s.topic)), messageType(s), 0, 0, 0.0});
  }
  if (slots.size() > 1) {
    d.sync = detail::makeErasedSync(int(slots.size()), options_.approxSync, options_.queueSize,
                                    options_.approxSyncMaxInterval,
                                    [&d](const std::vector<detail::ErasedPtr>& set) { d.deliver(set); });
  }
  for (int i = 0; i < int(slots.size()); ++i) d.subscribeSlot(nh, i);
  d.watch = nh.createWallTimer(ros::WallDuration(1.0), &Impl::onWatch, &d);
  std::string list;
  for (const TopicStatus& s : d.status) list += "\n   " + s.topic + " [" + s.type + "]";
  ROS_INFO("%s subscribed to (%s):%s", name.c_str(), describePolicy(options_).c_str(), list.c_str());
  return true;
}

std::vector<std::string> DataSubscriber::topics() const {
  std::vector<std::string> out;
  for (const TopicStatus& s : impl_->status) out.push_back(s.topic);
  return out;
}

std::string DataSubscriber::warningText(double seconds) const { return impl_->warningText(seconds); }

long DataSubscriber::delivered() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->delivered;
}

long DataSubscriber::droppedBadStamps() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->dropped;
}

long DataSubscriber::droppedInSync() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->drops.droppedInSync();
}

long DataSubscriber::missingFromStamps() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->drops.missingFromStamps();
}

long DataSubscriber::setsLost() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->drops.setsLost();
}

}  // namespace rtabmap_sync

#include "rtabmap_conversions/DatasetBag.h"

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <ros/message_traits.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <vector>

#include "rtabmap_conversions/BagLayout.h"
#include "rtabmap_conversions/CameraInfoConversions.h"
#include "rtabmap_conversions/ImageConversions.h"
#include "rtabmap_conversions/ImuConversions.h"
#include "rtabmap_conversions/LaserScanConversions.h"
#include "rtabmap_conversions/OdometryConversions.h"
#include "rtabmap_conversions/PointCloudConversions.h"
#include "rtabmap_conversions/TransformConversions.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap_conversions {

namespace {

// Records are held back until the first sensor frame and kHoldBackSeconds of data after the
// first record, so that /tf_static starts with the mountings of every sensor (an IMU whose
// first sample comes a few ms after the first image, ...); beyond kMaxHeldBack records (a
// long IMU-only prefix) the bag starts with what is known, and later mountings add a
// /tf_static message.
constexpr double kHoldBackSeconds = 1.0;
constexpr size_t kMaxHeldBack = 100000;
const char* const kCallerId = "/rtabmap_bag";

rosbag::compression::CompressionType compressionOf(const std::string& name) {
  if (name == "none" || name.empty()) return rosbag::compression::Uncompressed;
  if (name == "bz2") return rosbag::compression::BZ2;
  if (name == "lz4") return rosbag::compression::LZ4;
  throw rtabmap::Error("unknown bag compression '" + name + "'; expected none, bz2 or lz4");
}

bool sameTransform(const rtabmap::Transform& a, const rtabmap::Transform& b) {
  if (a.isNull() || b.isNull()) return a.isNull() == b.isNull();
  return (a.toMatrix4d() - b.toMatrix4d()).cwiseAbs().maxCoeff() < 1e-9;
}

std_msgs::Header headerOf(const ros::Time& stamp, const std::string& frame) {
  std_msgs::Header h;
  h.stamp = stamp;
  h.frame_id = frame;
  return h;
}

}  // namespace

struct DatasetBagWriter::Impl {
  rosbag::Bag bag;
  std::string path;
  BagWriterOptions options;
  BagSummary summary;
  bool open = false;
  bool offsetKnown = false;
  bool started = false;  // /tf_static written, records flow straight through
  bool sawFrame = false;
  std::vector<rtabmap::DatasetRecord> heldBack;
  bag::StaticTransforms statics;
  double lastTime = -std::numeric_limits<double>::infinity();
  double lastOdomTime = -std::numeric_limits<double>::infinity();
  double lastWritten = 0.0;  // bag time of the latest message written
  std::map<std::string, boost::shared_ptr<ros::M_string>> connectionHeaders;
  std::set<std::string> warnedMountings;  // one warning per frame whose mounting changes

  // Every topic gets an explicit connection header: rosbag play re-advertises a topic as
  // latched only when its recorded header says latching=1 (wanted for /tf_static alone).
  template <typename M>
  void write(const std::string& topic, const ros::Time& time, const M& msg) {
    auto& header = connectionHeaders[topic];
    if (!header) {
      header = boost::make_shared<ros::M_string>();
      (*header)["callerid"] = kCallerId;
      (*header)["type"] = ros::message_traits::datatype<M>();
      (*header)["md5sum"] = ros::message_traits::md5sum<M>();
      (*header)["message_definition"] = ros::message_traits::definition<M>();
      (*header)["latching"] = topic == bag::kTfStaticTopic ? "1" : "0";
    }
    bag.write(topic, time, msg, header);
    const double t = time.toSec();
    if (summary.messages == 0) summary.startTime = t;
    summary.startTime = std::min(summary.startTime, t);
    summary.endTime = std::max(summary.endTime, t);
    lastWritten = std::max(lastWritten, t);
    ++summary.messages;
    ++summary.messagesPerTopic[topic];
  }

  ros::Time timeOf(double stamp) const { return ros::Time(stamp + summary.timeOffset); }

  // Written a microsecond before the records that need it: rosbag orders messages of equal
  // time arbitrarily, and a sensor message played before its mounting would be dropped (or
  // waited for) by the tf lookups of the nodes. Static transforms do not expire, so their stamp
  // plays no other part.
  void writeStatics(const ros::Time& recordTime) {
    ros::Time time = recordTime;
    if (recordTime.toSec() - 1e-6 >= std::max(lastWritten, 1e-9)) time = recordTime - ros::Duration(0, 1000);
    tf2_msgs::TFMessage msg;
    for (const auto& [child, st] : statics) {
      geometry_msgs::TransformStamped t;
      t.header = headerOf(time, st.parent);
      t.child_frame_id = child;
      t.transform = transformToMsg(st.transform);
      msg.transforms.push_back(t);
    }
    if (!msg.transforms.empty()) write(bag::kTfStaticTopic, time, msg);
  }

  // Merges the mountings of `data`; true if one is new or changed.
  bool updateStatics(const rtabmap::SensorData& data, double stamp) {
    bag::StaticTransforms merged = statics;
    bag::addStaticTransforms(data, merged);
    bool changed = false;
    for (const auto& [child, st] : merged) {
      auto it = statics.find(child);
      if (it == statics.end()) {
        changed = true;
      } else if (it->second.parent != st.parent || !sameTransform(it->second.transform, st.transform)) {
        if (warnedMountings.insert(child).second) {
          RTABMAP_WARN("the mounting of '" << child << "' changes at t=" << stamp
                                           << " s; /tf_static is written again with the new one");
        }
        changed = true;
      }
    }
    statics = std::move(merged);
    return changed;
  }

  void writeOdometry(const rtabmap::SensorData& data, const ros::Time& time) {
    if (data.odomPose().isNull() || time.toSec() == lastOdomTime) return;
    lastOdomTime = time.toSec();
    write(bag::kOdomTopic, time,
          odometryToMsg(data.odomPose(), data.odomCovariance(), headerOf(time, bag::kOdomFrame), bag::kBaseFrame));
    tf2_msgs::TFMessage tf;
    geometry_msgs::TransformStamped t;
    t.header = headerOf(time, bag::kOdomFrame);
    t.child_frame_id = bag::kBaseFrame;
    t.transform = transformToMsg(data.odomPose());
    tf.transforms.push_back(t);
    write(bag::kTfTopic, time, tf);
  }

  void writeScan(const rtabmap::LaserScan& scan, const ros::Time& time) {
    const std_msgs::Header header = headerOf(time, bag::scanFrame(scan));
    const std::string topic = bag::scanTopic(scan);
    if (topic == bag::kScanTopic) {
      std::string why;
      std::optional<sensor_msgs::LaserScan> msg = laserScanToMsg(scan, header, &why);
      if (!msg) throw rtabmap::FormatError("scan at t=" + std::to_string(time.toSec()) + ": " + why);
      write(topic, time, *msg);
    } else {
      write(topic, time, laserScanToCloudMsg(scan, header));
    }
  }

  void writeImages(const rtabmap::SensorData& data, const ros::Time& time) {
    if (data.isStereo()) {
      const std_msgs::Header left = headerOf(time, bag::kLeftOpticalFrame);
      const std_msgs::Header right = headerOf(time, bag::kRightOpticalFrame);
      if (!data.imageRaw().empty()) write(bag::kLeftTopic, time, imageToMsg(data.imageRaw(), left));
      if (!data.depthOrRightRaw().empty()) write(bag::kRightTopic, time, imageToMsg(data.depthOrRightRaw(), right));
      sensor_msgs::CameraInfo leftInfo, rightInfo;
      stereoModelToMsgs(data.stereoCameraModels().front(), left, right, leftInfo, rightInfo);
      write(bag::kLeftInfoTopic, time, leftInfo);
      write(bag::kRightInfoTopic, time, rightInfo);
      return;
    }
    if (data.imageRaw().empty()) return;
    const std_msgs::Header header = headerOf(time, bag::kRgbOpticalFrame);
    write(bag::kRgbTopic, time, imageToMsg(data.imageRaw(), header));
    if (!data.depthOrRightRaw().empty()) write(bag::kDepthTopic, time, imageToMsg(data.depthOrRightRaw(), header));
    // Plain image folders may come without calibration: their images are published alone.
    if (data.cameraModels().size() == 1 && data.cameraModels().front().isValidForProjection()) {
      write(bag::kRgbInfoTopic, time, cameraModelToMsg(data.cameraModels().front(), header));
    }
  }

  void process(const rtabmap::DatasetRecord& record) {
    const ros::Time time = timeOf(record.stamp);
    if (time.toSec() < lastTime) ++summary.outOfOrder;
    lastTime = std::max(lastTime, time.toSec());
    rtabmap::SensorData data = record.data;
    // Readers may hand over compressed parts only; the bag holds raw images and scans.
    data.uncompress();
    if (updateStatics(data, record.stamp)) writeStatics(time);
    writeOdometry(data, time);
    if (!data.groundTruth().isNull()) {
      Covariance6 zero = Covariance6::Zero();
      write(bag::kGroundTruthTopic, time,
            odometryToMsg(data.groundTruth(), zero, headerOf(time, bag::kWorldFrame), bag::kBaseFrame));
    }
    if (!data.imu().empty()) write(bag::kImuTopic, time, imuToMsg(data.imu(), headerOf(time, bag::kImuFrame)));
    if (record.kind != rtabmap::DatasetRecord::Kind::kFrame) return;
    if (!data.laserScanRaw().empty() || data.laserScanRaw().hasBeamGeometry()) writeScan(data.laserScanRaw(), time);
    writeImages(data, time);
  }

  // The mountings of everything held back (the first seen of each frame: a later change is
  // caught by process()), one /tf_static at the first stamp, then the records.
  void start() {
    started = true;
    if (heldBack.empty()) return;
    for (const rtabmap::DatasetRecord& r : heldBack) {
      bag::StaticTransforms mountings;
      bag::addStaticTransforms(r.data, mountings);
      for (auto& entry : mountings) statics.insert(entry);
    }
    writeStatics(timeOf(heldBack.front().stamp));
    std::vector<rtabmap::DatasetRecord> records;
    records.swap(heldBack);
    for (const rtabmap::DatasetRecord& r : records) process(r);
  }
};

DatasetBagWriter::DatasetBagWriter(const std::string& path, const BagWriterOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->options = options;
  try {
    impl_->bag.open(path, rosbag::bagmode::Write);
    impl_->bag.setCompression(compressionOf(options.compression));
  } catch (const rosbag::BagException& e) {
    throw rtabmap::Error("cannot write the bag " + path + ": " + e.what());
  }
  impl_->open = true;
}

DatasetBagWriter::~DatasetBagWriter() {
  if (!impl_->open) return;
  try {
    close();
  } catch (const std::exception& e) {
    RTABMAP_ERROR("closing the bag " << impl_->path << ": " << e.what());
  }
}

void DatasetBagWriter::add(const rtabmap::DatasetRecord& record) {
  Impl& d = *impl_;
  if (!d.open) throw rtabmap::Error("DatasetBagWriter::add after close()");
  if (!std::isfinite(record.stamp)) {
    throw rtabmap::FormatError("a dataset record has a non-finite stamp (" + std::to_string(record.stamp) + ")");
  }
  if (!d.offsetKnown) {
    d.offsetKnown = true;
    d.summary.timeOffset = std::isnan(d.options.timeOffset)
                               ? (record.stamp < 1.0 ? std::ceil(1.0 - record.stamp) : 0.0)
                               : d.options.timeOffset;
  }
  if (record.stamp + d.summary.timeOffset < 1e-9 || record.stamp + d.summary.timeOffset > 4294967295.0) {
    throw rtabmap::FormatError("record stamp " + std::to_string(record.stamp) + " s (+ offset " +
                               std::to_string(d.summary.timeOffset) + " s) is outside the times a bag can hold");
  }
  ++d.summary.records;
  const bool frame = record.kind == rtabmap::DatasetRecord::Kind::kFrame;
  if (frame) ++d.summary.frames;
  try {
    if (!d.started) {
      // Checked now rather than when the held-back records are written: the error then names
      // the record the caller just added.
      bag::StaticTransforms layoutCheck;
      bag::addStaticTransforms(record.data, layoutCheck);
      d.heldBack.push_back(record);
      d.sawFrame = d.sawFrame || frame;
      const bool windowDone = record.stamp - d.heldBack.front().stamp >= kHoldBackSeconds;
      if ((d.sawFrame && windowDone) || d.heldBack.size() >= kMaxHeldBack) d.start();
      return;
    }
    d.process(record);
  } catch (const rosbag::BagException& e) {
    throw rtabmap::Error("writing the bag " + d.path + ": " + e.what());
  }
}

BagSummary DatasetBagWriter::close() {
  Impl& d = *impl_;
  if (!d.open) return d.summary;
  try {
    if (!d.started) d.start();
    d.bag.close();
  } catch (const rosbag::BagException& e) {
    d.open = false;
    throw rtabmap::Error("closing the bag " + d.path + ": " + e.what());
  }
  d.open = false;
  std::error_code ec;
  d.summary.bytes = std::filesystem::file_size(d.path, ec);
  return d.summary;
}

const BagSummary& DatasetBagWriter::summary() const { return impl_->summary; }

BagSummary convertDatasetToBag(rtabmap::DatasetReader& reader, const std::string& path,
                               const BagWriterOptions& options,
                               const std::function<void(const BagSummary&)>& progress) {
  DatasetBagWriter writer(path, options);
  rtabmap::DatasetRecord record;
  while (reader.next(record)) {
    writer.add(record);
    if (progress) progress(writer.summary());
  }
  return writer.close();
}

}  // namespace rtabmap_conversions

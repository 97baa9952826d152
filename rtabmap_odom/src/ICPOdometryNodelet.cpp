// icp_odometry: lidar odometry (S2M or S2S, Odom/Strategy) from a 2D scan (`scan`, default) or
// a 3D cloud (`scan_cloud`, subscribe_scan_cloud), registered by the core's ICP (Icp/*).
//
// Own parameters (classic names; each sets the core ICP step that does it, see
// rtabmap_odom/NodeParameters.h): scan_range_min, scan_range_max (m), scan_voxel_size (m),
// scan_downsampling_step, scan_normal_k, scan_normal_radius (m).
// deskewing: not implemented. Correcting a scan for the motion during its sweep needs each
// point's time and the motion over the sweep; neither LaserScan nor the clouds we read carry
// per-point times here, so a deskewing=true request is reported and ignored.
// Common parameters, topics and services: OdometryNodelet.h.
#include <pluginlib/class_list_macros.hpp>

#include "OdometryNodelet.h"
#include "rtabmap_odom/NodeParameters.h"
#include "rtabmap_sync/FrameAssembly.h"

namespace rtabmap_ros {

class ICPOdometryNodelet : public OdometryNodelet {
 public:
  ICPOdometryNodelet() : OdometryNodelet(true) {}

 private:
  rtabmap_sync::SubscribeOptions defaultSubscribeOptions() const override {
    rtabmap_sync::SubscribeOptions o;
    o.subscribeScan = !cloud_;  // subscribe_scan_cloud alone means the cloud, without a conflict
    return o;
  }

  std::vector<std::string> parameterNames() const override {
    return {"scan_range_min", "scan_range_max", "scan_voxel_size", "scan_downsampling_step",
            "scan_normal_k", "scan_normal_radius", "deskewing"};
  }

  void readParameters(ros::NodeHandle& pnh, rtabmap::ParametersMap& core) override {
    pnh.param("subscribe_scan_cloud", cloud_, cloud_);
    rtabmap_odom::ScanOptions o;
    pnh.param("scan_range_min", o.rangeMin, o.rangeMin);
    pnh.param("scan_range_max", o.rangeMax, o.rangeMax);
    pnh.param("scan_voxel_size", o.voxelSize, o.voxelSize);
    pnh.param("scan_downsampling_step", o.downsamplingStep, o.downsamplingStep);
    pnh.param("scan_normal_k", o.normalK, o.normalK);
    pnh.param("scan_normal_radius", o.normalRadius, o.normalRadius);
    bool deskewing = false;
    if (pnh.getParam("deskewing", deskewing) && deskewing) {
      NODELET_WARN("%s: deskewing is not implemented (no per-point times); scans are used as they are.",
                   getName().c_str());
    }
    std::string why;
    if (!o.IsValid(&why)) {
      NODELET_ERROR("%s: %s; the scan options are ignored.", getName().c_str(), why.c_str());
      return;
    }
    std::vector<std::string> notes;
    core = rtabmap_odom::applyScanOptions(o, core, &notes);
    for (const std::string& n : notes) NODELET_WARN("%s: %s", getName().c_str(), n.c_str());
  }

  std::optional<rtabmap::SensorData> makeFrame(const rtabmap_sync::SyncedData& d, std::string* error) override {
    const std_msgs::Header& header = d.scan ? d.scan->header : d.scanCloud->header;
    const char* topic = d.scan ? "scan" : "scan_cloud";
    const rtabmap::Transform local = sensorPose(header.frame_id, header.stamp, error);
    if (local.isNull()) return std::nullopt;
    std::optional<rtabmap::LaserScan> scan = rtabmap_sync::syncedScan(d.scan, d.scanCloud, local, error);
    if (!scan) return std::nullopt;
    if (scan->empty()) {
      if (error) *error = std::string(topic) + ": no valid point (every range NaN, infinite or out of limits)";
      return std::nullopt;
    }
    return rtabmap::SensorData(*scan, 0, header.stamp.toSec());
  }

  rtabmap::LaserScan frameCloud(const rtabmap::SensorData& frame) const override {
    return frame.laserScanRaw();  // scanInFrame applies its local transform
  }

  bool cloud_ = false;  // subscribe_scan_cloud
};

}  // namespace rtabmap_ros

PLUGINLIB_EXPORT_CLASS(rtabmap_ros::ICPOdometryNodelet, nodelet::Nodelet)

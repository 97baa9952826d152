// icp_odometry: lidar odometry (S2M or S2S, Odom/Strategy) from a 2D scan (`scan`, default) or
// a 3D cloud (`scan_cloud`, subscribe_scan_cloud), registered by the core's ICP (Icp/*).
//
// Own parameters (classic names; each sets the core ICP step that does it, see
// rtabmap_odom/NodeParameters.h): scan_range_min, scan_range_max (m), scan_voxel_size (m),
// scan_downsampling_step, scan_normal_k, scan_normal_radius (m).
// deskewing (false): move each point of a sweep to where it would have been measured at the
// message's stamp (rtabmap_conversions/Deskewing.h). Point times come from the LaserScan's
// time_increment (projected through laser_geometry) or the cloud's time field; the motion over
// the sweep from tf through guess_frame_id when set (wheel odometry), else turned as the imu
// topic's gyroscope measured (moving at the odometry's last velocity), else from the odometry's
// own last motion (constant velocity). A frame that cannot be deskewed is used as it is, with a
// throttled warning saying why.
// Common parameters, topics and services: OdometryNodelet.h.
#include <pluginlib/class_list_macros.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <optional>
#include <vector>

#include "OdometryNodelet.h"
#include "rtabmap_conversions/Deskewing.h"
#include "rtabmap_conversions/PointCloudConversions.h"
#include "rtabmap_odom/NodeParameters.h"
#include "rtabmap_odom/PrivateParameters.h"
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
    pnh.param("deskewing", deskewing_, deskewing_);
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
    std::optional<rtabmap::LaserScan> scan;
    if (deskewing_) scan = deskewedScan(d, local);
    if (!scan) scan = rtabmap_sync::syncedScan(d.scan, d.scanCloud, local, error);
    if (!scan) return std::nullopt;
    if (scan->empty()) {
      if (error) *error = std::string(topic) + ": no valid point (every range NaN, infinite or out of limits)";
      return std::nullopt;
    }
    return rtabmap::SensorData(*scan, 0, header.stamp.toSec());
  }

  // The synchronised scan or cloud deskewed (see the top of the file); nullopt (with a throttled
  // warning) when it cannot be: no point times, no tf, no velocity yet.
  std::optional<rtabmap::LaserScan> deskewedScan(const rtabmap_sync::SyncedData& d, const rtabmap::Transform& local) {
    sensor_msgs::PointCloud2 cloud = d.scan ? rtabmap_conversions::timedCloudFromScan(*d.scan) : *d.scanCloud;
    std::string why;
    std::optional<std::vector<double>> times = rtabmap_conversions::pointTimes(cloud, &why);
    std::optional<rtabmap_conversions::SweepMotion> motion;
    if (times && !times->empty()) motion = sweepMotion(cloud.header, *times, local, &why);
    std::optional<rtabmap::LaserScan> scan;
    if (motion && rtabmap_conversions::deskewCloud(cloud, *times, *motion, &why)) {
      // A scan keeps its sensor's range limits (the cloud has none).
      const double rangeMin = d.scan ? d.scan->range_min : 0.0, rangeMax = d.scan ? d.scan->range_max : 0.0;
      scan = rtabmap_conversions::laserScanFromCloudMsg(cloud, local, &why, rangeMin, rangeMax);
      if (scan && d.scan) scan = rtabmap_conversions::planarScan(*scan);
    }
    if (!scan && !why.empty() && deskewWarnings_.due(rtabmap_odom::throttleKey(why))) {
      NODELET_WARN("%s: frame at %.6f not deskewed: %s", getName().c_str(), cloud.header.stamp.toSec(), why.c_str());
    }
    return scan;
  }

  // The sensor's motion over the sweep: tf through guess_frame_id; else the rotation the imu
  // topic's gyroscope measured with the odometry's last velocity; else the last odometry motion;
  // each moved into the sensor frame.
  std::optional<rtabmap_conversions::SweepMotion> sweepMotion(const std_msgs::Header& header,
                                                               const std::vector<double>& times,
                                                               const rtabmap::Transform& local, std::string* why) {
    if (!guessFrameId().empty()) {
      const auto [first, last] = std::minmax_element(times.begin(), times.end());
      return rtabmap_conversions::SweepMotion::fromTf(tfBuffer(), guessFrameId(), header.frame_id, header.stamp,
                                                      *first, *last, waitForTransform(), why);
    }
    double interval = 0.0;
    const rtabmap::Transform& motion = lastMotion(&interval);
    if (std::optional<rtabmap_conversions::SweepMotion> m = gyroSweepMotion(header, times, local, motion, interval)) {
      return m;
    }
    if (motion.isNull()) return std::nullopt;  // first frame, lost or reset: nothing to say
    return rtabmap_conversions::SweepMotion::fromVelocity(local.inverse() * motion * local, interval);
  }

  // The sweep turned as the gyroscope measured between the stamp and the first / last point
  // times, moving at the odometry's last velocity (none yet: only turning); none without
  // gyroscope samples covering the sweep.
  std::optional<rtabmap_conversions::SweepMotion> gyroSweepMotion(const std_msgs::Header& header,
                                                                   const std::vector<double>& times,
                                                                   const rtabmap::Transform& local,
                                                                   const rtabmap::Transform& motion, double interval) {
    const double stamp = header.stamp.toSec();
    auto rotationTo = [&](double dt) -> std::optional<Eigen::Matrix3d> {
      if (dt == 0.0) return Eigen::Matrix3d::Identity();
      if (dt > 0.0) return imuRotationBetween(stamp, stamp + dt);
      const std::optional<Eigen::Matrix3d> back = imuRotationBetween(stamp + dt, stamp);
      if (!back) return std::nullopt;
      return Eigen::Matrix3d(back->transpose());
    };
    const auto [first, last] = std::minmax_element(times.begin(), times.end());
    const std::optional<Eigen::Matrix3d> atFirst = rotationTo(*first), atLast = rotationTo(*last);
    if (!atFirst || !atLast) return std::nullopt;
    const Eigen::Vector3d velocity =
        motion.isNull() || interval <= 0.0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(motion.translation() / interval);
    auto inSensor = [&](const Eigen::Matrix3d& rotation, double dt) {
      Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
      base.linear() = rotation;
      base.translation() = velocity * dt;
      return local.inverse() * rtabmap::Transform(base) * local;
    };
    return rtabmap_conversions::SweepMotion::fromEnds(inSensor(*atFirst, *first), *first, inSensor(*atLast, *last),
                                                      *last);
  }

  rtabmap::LaserScan frameCloud(const rtabmap::SensorData& frame) const override {
    return frame.laserScanRaw();  // scanInFrame applies its local transform
  }

  bool cloud_ = false;  // subscribe_scan_cloud
  bool deskewing_ = false;
  rtabmap_sync::LogThrottle deskewWarnings_;
};

}  // namespace rtabmap_ros

PLUGINLIB_EXPORT_CLASS(rtabmap_ros::ICPOdometryNodelet, nodelet::Nodelet)

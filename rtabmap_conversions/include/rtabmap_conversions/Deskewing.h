#pragma once
// Lidar deskewing (icp_odometry `deskewing`): a spinning lidar measures the points of one sweep
// over its whole duration (0.1 s for a 10 Hz lidar) while the robot moves, so a sweep taken while
// turning at 1 rad/s bends every wall by up to 0.1 rad. Each point is moved to where the sensor
// would have measured it at the message's stamp, from its own time in the sweep and the sensor's
// motion over the sweep (from tf through a fixed frame, e.g. wheel odometry, from an IMU's
// gyroscope, or from a constant-velocity model of the odometry itself).
//
// Point times: a sensor_msgs/LaserScan gives them through its time_increment (laser_geometry
// projects the scan with a per-beam "stamps" channel); a PointCloud2 needs a per-point time
// field: "t" (uint32 nanoseconds since the stamp, Ouster), "time" (float32 seconds relative to
// the stamp, Velodyne), "stamps" (laser_geometry), or "timestamp" (float64 seconds, absolute as
// Hesai writes it, or relative). Times above 1e6 s are taken as absolute and made relative to
// the stamp.
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2/buffer_core.h>

#include <optional>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap_conversions {

// The sensor's motion over a sweep: at(dt) is the pose of the sensor at stamp + dt in its own
// frame at the stamp (identity at dt = 0).
class SweepMotion {
 public:
  // From tf: the motion of sensorFrame through fixedFrame between the stamp and the first /
  // last point times, waiting up to waitSeconds for each; in between, interpolated (linear
  // translation, slerp rotation), as laser_geometry does. nullopt and *error naming the frames
  // when tf cannot give them (the sweep's end is often not yet in tf: wait for it).
  static std::optional<SweepMotion> fromTf(const tf2::BufferCore& buffer, const std::string& fixedFrame,
                                           const std::string& sensorFrame, const ros::Time& stamp, double firstDt,
                                           double lastDt, double waitSeconds, std::string* error = nullptr);
  // Constant velocity: `motion` of the sensor over `interval` seconds (the last odometry
  // motion, in the sensor frame), scaled to any dt. interval must be > 0.
  static SweepMotion fromVelocity(const rtabmap::Transform& motion, double interval);
  // The sensor's poses at the first and last point times (in its frame at the stamp), e.g.
  // turned as an IMU's gyroscope measured; in between, interpolated as fromTf's.
  static SweepMotion fromEnds(const rtabmap::Transform& atFirst, double firstDt, const rtabmap::Transform& atLast,
                              double lastDt);

  rtabmap::Transform at(double dt) const;

 private:
  SweepMotion(const rtabmap::Transform& first, double firstDt, const rtabmap::Transform& last, double lastDt);
  rtabmap::Transform first_, last_;
  double firstDt_ = 0.0, lastDt_ = 0.0;
};

// The scan as a cloud in its own frame through laser_geometry, with the fields x y z,
// intensity (when the scan has intensities) and "stamps" (each beam's time since the stamp:
// index * time_increment). Beams without a valid return are left out.
sensor_msgs::PointCloud2 timedCloudFromScan(const sensor_msgs::LaserScan& scan);

// Each point's time relative to cloud.header.stamp (see the field names above). Errors: no
// time field, a time field outside the point's bytes, a big-endian cloud.
std::optional<std::vector<double>> pointTimes(const sensor_msgs::PointCloud2& cloud, std::string* error = nullptr);

// Moves x, y, z of every point to where the sensor would have measured it at the stamp
// (p' = motion.at(t) * p). x, y, z must be float32; times must have one value per point.
bool deskewCloud(sensor_msgs::PointCloud2& cloud, const std::vector<double>& times, const SweepMotion& motion,
                 std::string* error = nullptr);

// A planar scan (XY, or XYI with intensities) from a cloud of a planar lidar: z dropped (the
// sensor's plane), no beam geometry (the points no longer sit on their beams).
rtabmap::LaserScan planarScan(const rtabmap::LaserScan& cloud);

}  // namespace rtabmap_conversions

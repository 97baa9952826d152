#pragma once
// Random ROS messages for the conversion fuzz targets: every field from the fuzz bytes, sizes
// bounded (a real subscriber never holds gigabytes) but free to disagree with each other.
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include "rtabmap_ros/RGBDImage.h"
#include "ByteReader.h"

namespace rtabmap::fuzz {

inline void fillHeader(ByteReader& r, std_msgs::Header& h) {
  h.seq = r.take<uint32_t>();
  h.stamp.sec = r.takeSmall(2000000000u);
  h.stamp.nsec = r.takeSmall(999999999u);
  h.frame_id = r.takeName({"camera_optical", "laser", "base_link", ""});
}

inline sensor_msgs::CameraInfo randomCameraInfo(ByteReader& r) {
  sensor_msgs::CameraInfo m;
  fillHeader(r, m.header);
  m.width = r.takeSize(640);
  m.height = r.takeSize(480);
  m.distortion_model = r.takeName({"plumb_bob", "rational_polynomial", "equidistant", "fisheye", ""});
  m.D.resize(r.takeSmall(14));
  for (double& d : m.D) d = r.takeReal<double>() / 64.0;
  for (double& k : m.K) k = r.takeReal<double>();
  for (double& v : m.R) v = r.takeReal<double>() / 4096.0;
  for (double& p : m.P) p = r.takeReal<double>();
  m.binning_x = r.takeSize(4);
  m.binning_y = r.takeSize(4);
  m.roi.x_offset = r.takeSize(640);
  m.roi.y_offset = r.takeSize(480);
  m.roi.width = r.takeSize(640);
  m.roi.height = r.takeSize(480);
  m.roi.do_rectify = r.take<uint8_t>() & 1;
  return m;
}

inline sensor_msgs::Image randomImage(ByteReader& r) {
  sensor_msgs::Image m;
  fillHeader(r, m.header);
  m.width = r.takeSize(64);
  m.height = r.takeSize(48);
  m.encoding = r.takeName({"rgb8", "bgr8", "rgba8", "bgra8", "mono8", "mono16", "16UC1", "32FC1",
                           "8UC1", "8UC3", "16SC1", "64FC1", "bayer_rggb8", "yuv422"});
  m.is_bigendian = r.take<uint8_t>() & 1;
  m.step = r.takeSize(64 * 8);
  m.data = r.takeBytes(64 * 48 * 4 + 64);
  return m;
}

inline sensor_msgs::CompressedImage randomCompressedImage(ByteReader& r) {
  sensor_msgs::CompressedImage m;
  fillHeader(r, m.header);
  m.format = r.takeName({"jpeg", "png", "rgb8; jpeg compressed bgr8", "16UC1; compressedDepth png",
                         "32FC1; compressedDepth png", "16UC1; compressedDepth rvl",
                         "32FC1; rtabmap zlib", "bgr8; png compressed bgr8"});
  m.data = r.takeBytes(8192);
  return m;
}

inline sensor_msgs::LaserScan randomLaserScan(ByteReader& r) {
  sensor_msgs::LaserScan m;
  fillHeader(r, m.header);
  m.angle_min = r.takeReal<float>() / 512.0f;
  m.angle_max = r.takeReal<float>() / 512.0f;
  m.angle_increment = r.takeReal<float>() / 65536.0f;
  m.time_increment = r.takeReal<float>();
  m.scan_time = r.takeReal<float>();
  m.range_min = r.takeReal<float>() / 64.0f;
  m.range_max = r.takeReal<float>();
  m.ranges.resize(r.takeSmall(4096));
  for (float& v : m.ranges) v = r.takeReal<float>() / 64.0f;
  m.intensities.resize(r.take<uint8_t>() < 128 ? 0 : r.takeSmall(4096));
  for (float& v : m.intensities) v = r.takeReal<float>();
  return m;
}

inline sensor_msgs::PointCloud2 randomPointCloud2(ByteReader& r) {
  sensor_msgs::PointCloud2 m;
  fillHeader(r, m.header);
  m.height = r.takeSize(16);
  m.width = r.takeSize(256);
  m.fields.resize(r.takeSmall(8));
  for (sensor_msgs::PointField& f : m.fields) {
    f.name = r.takeName({"x", "y", "z", "intensity", "i", "rgb", "rgba", "normal_x", "normal_y",
                         "normal_z", "ring"});
    f.offset = r.takeSize(64);
    f.datatype = static_cast<uint8_t>(r.takeSize(9));
    f.count = r.takeSize(2);
  }
  m.is_bigendian = r.take<uint8_t>() < 16;
  m.point_step = r.takeSize(64);
  m.row_step = r.takeSize(64 * 256);
  m.is_dense = r.take<uint8_t>() & 1;
  m.data = r.takeBytes(32768);
  return m;
}

inline rtabmap_ros::RGBDImage randomRgbdImage(ByteReader& r) {
  rtabmap_ros::RGBDImage m;
  fillHeader(r, m.header);
  m.rgb_camera_info = randomCameraInfo(r);
  m.depth_camera_info = r.take<uint8_t>() < 128 ? m.rgb_camera_info : randomCameraInfo(r);
  if (r.take<uint8_t>() < 160) m.rgb = randomImage(r);
  else m.rgb_compressed = randomCompressedImage(r);
  if (r.take<uint8_t>() < 160) m.depth = randomImage(r);
  else m.depth_compressed = randomCompressedImage(r);
  m.key_points.resize(r.takeSmall(32));
  for (rtabmap_ros::KeyPoint& k : m.key_points) {
    k.pt.x = r.takeReal<float>();
    k.pt.y = r.takeReal<float>();
    k.size = r.takeReal<float>();
    k.angle = r.takeReal<float>();
    k.response = r.takeReal<float>();
    k.octave = r.take<int32_t>();
    k.class_id = r.take<int32_t>();
  }
  m.points.resize(r.take<uint8_t>() < 128 ? m.key_points.size() : r.takeSmall(32));
  for (rtabmap_ros::Point3f& p : m.points) {
    p.x = r.takeReal<float>();
    p.y = r.takeReal<float>();
    p.z = r.takeReal<float>();
  }
  m.descriptors = r.takeBytes(32 * 64);
  return m;
}

}  // namespace rtabmap::fuzz

#pragma once
// A laser scan as a list of points in the sensor frame: 2D (XY, lidars like the URG) or 3D
// (XYZ, Velodyne), optionally with intensity, RGB and normals. Points are stored in one
// 1xN cv::Mat of CV_32FC(k), the channels in the order of the format name (e.g. XYZINormal:
// x y z i nx ny nz), which is compact, compresses well and is what the database stores.
//
// Range limits are those of the sensor (points beyond were dropped); maxPoints is the number
// of beams of a full scan, used to judge how much of a scan an ICP matched.
//
// Channel counts: XY 2, XYI 3, XYNormal 5 (x y nx ny nz), XYINormal 6, XYZ 3, XYZI 4, XYZRGB 4
// (rgb packed into one float as PCL does: the bits of 0x00RRGGBB), XYZNormal 6, XYZINormal 7,
// XYZRGBNormal 7. Normals always have 3 components.
#include <opencv2/core/mat.hpp>

#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

class LaserScan {
 public:
  enum Format {
    kUnknown = 0,
    kXY = 1,
    kXYI = 2,
    kXYNormal = 3,
    kXYINormal = 4,
    kXYZ = 5,
    kXYZI = 6,
    kXYZRGB = 7,
    kXYZNormal = 8,
    kXYZINormal = 9,
    kXYZRGBNormal = 10,
  };

  LaserScan();
  // data: 1xN (or Nx1, stored as 1xN) CV_32FC(channels(format)); throws FormatError if the
  // depth or channel count mismatches, or for non-empty data with kUnknown. Data is shared,
  // not copied.
  LaserScan(const cv::Mat& data, int maxPoints, double rangeMin, double rangeMax, Format format,
            const Transform& localTransform = Transform::Identity());
  // A planar scan from polar ranges (sensor_msgs/LaserScan): beams that are NaN, infinite, or
  // outside [rangeMin, rangeMax] are dropped. maxPoints = ranges.size().
  static LaserScan fromRanges(const std::vector<float>& ranges, double angleMin,
                              double angleIncrement, double rangeMin, double rangeMax,
                              const Transform& localTransform = Transform::Identity(),
                              const std::vector<float>& intensities = {});

  static int channels(Format format);
  static bool is2d(Format format);
  static bool hasNormals(Format format);
  static bool hasIntensity(Format format);
  static bool hasRGB(Format format);
  static std::string formatName(Format format);

  const cv::Mat& data() const { return data_; }
  Format format() const { return format_; }
  int size() const { return data_.cols; }
  bool empty() const { return data_.empty(); }
  bool isEmpty() const { return empty(); }
  int maxPoints() const { return maxPoints_; }
  double rangeMin() const { return rangeMin_; }
  double rangeMax() const { return rangeMax_; }
  const Transform& localTransform() const { return localTransform_; }
  void setLocalTransform(const Transform& t) { localTransform_ = t; }
  bool is2d() const { return is2d(format_); }
  bool hasNormals() const { return hasNormals(format_); }
  bool hasIntensity() const { return hasIntensity(format_); }
  bool hasRGB() const { return hasRGB(format_); }

  // Beam geometry of a planar scan from a rotating sensor (sensor_msgs/LaserScan): angle of
  // beam 0, of the last beam, and the increment, in the sensor frame. It tells which beams
  // returned nothing (no point at their angle), which the 2D grid ray-traces as free space up
  // to rangeMax and the rosbag converter writes back as +Inf ranges. Unknown (increment 0) for
  // 3D clouds and scans built from points.
  bool hasBeamGeometry() const { return angleIncrement_ != 0.0; }
  double angleMin() const { return angleMin_; }
  double angleMax() const { return angleMax_; }
  double angleIncrement() const { return angleIncrement_; }
  void setBeamGeometry(double angleMin, double angleMax, double angleIncrement);
  // Ranges per beam (sensor frame), +Inf where a beam has no point; empty without geometry.
  std::vector<float> toRanges() const;

  // Point i in the sensor frame (z = 0 for 2D formats).
  Eigen::Vector3f point(int i) const;
  // All points transformed by localTransform (sensor -> base frame), same format, identity
  // local transform. The beam geometry is dropped (it describes the sensor frame). Points and normals are rotated (points also translated); intensity and
  // rgb are untouched. A 2D format keeps no z: a planar scan stays in the base's plane.
  LaserScan transformedToBase() const;
  // Keeps only points with range in [rangeMin, rangeMax] from the sensor origin (0 = no limit)
  // and at most maxPoints by uniform downsampling (0 = all). The result's range limits are the
  // tighter of the old and new ones; when downsampled, its maxPoints shrinks in proportion so
  // a correspondence ratio against it stays comparable.
  LaserScan filtered(double rangeMin, double rangeMax, int maxPoints = 0) const;

 private:
  cv::Mat data_;
  Format format_;
  int maxPoints_;
  double rangeMin_;
  double rangeMax_;
  Transform localTransform_;
  double angleMin_ = 0.0;
  double angleMax_ = 0.0;
  double angleIncrement_ = 0.0;
};

}  // namespace rtabmap

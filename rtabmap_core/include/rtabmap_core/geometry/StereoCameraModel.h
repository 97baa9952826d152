#pragma once
// A rectified stereo pair: left and right pinhole models sharing fx, fy, cx, cy after
// rectification, with the baseline in the right P (Tx = -fx * baseline). The local transform
// is the left camera's.
#include <opencv2/core/mat.hpp>

#include <string>
#include <vector>

#include "rtabmap_core/geometry/CameraModel.h"

namespace rtabmap {

class StereoCameraModel {
 public:
  StereoCameraModel();
  // Already rectified pair (e.g. from two ROS CameraInfo of a rectified stereo driver).
  StereoCameraModel(const std::string& name, const CameraModel& left, const CameraModel& right);
  // Rectified pair from intrinsics only.
  StereoCameraModel(double fx, double fy, double cx, double cy, double baseline,
                    const Transform& localTransform = CameraModel::opticalRotation(),
                    const cv::Size& imageSize = cv::Size(0, 0));
  // Raw calibration: each camera's K and D, and the pose of the right camera in the left
  // camera frame (R, T as OpenCV stereoCalibrate gives: x_right = R * x_left + T). Computes the
  // rectification (R1, R2, P1, P2) with cv::stereoRectify, zero alpha (only valid pixels).
  // EuRoC's sensor.yaml gives T_BS per camera: T_right_left = T_BS_right^-1 * T_BS_left.
  // `localTransform` is the raw left camera's (base -> raw left optical frame); the model's
  // local transform is the *rectified* left camera's, localTransform * R1^T (R1 rotates raw
  // left coordinates into rectified ones), so 3D points from rectified images land right in
  // the base frame. Models are named name + "_left" / "_right". Throws FormatError on bad
  // shapes or an unknown image size.
  static StereoCameraModel fromRawCalibration(const std::string& name, const cv::Size& imageSize,
                                              const cv::Mat& K1, const cv::Mat& D1,
                                              const cv::Mat& K2, const cv::Mat& D2,
                                              const cv::Mat& R, const cv::Mat& T,
                                              const Transform& localTransform);

  const std::string& name() const { return name_; }
  bool isValidForProjection() const;   // both valid, baseline > 0
  bool isValidForRectification() const;
  const CameraModel& left() const { return left_; }
  const CameraModel& right() const { return right_; }
  double baseline() const;  // metres, > 0
  const Transform& localTransform() const { return left_.localTransform(); }
  void setLocalTransform(const Transform& t);

  // depth = fx * baseline / disparity (metres); 0 for disparity <= 0.
  double computeDepth(double disparity) const;
  // disparity = fx * baseline / depth (pixels); 0 for depth <= 0.
  double computeDisparity(double depth) const;

  void initRectificationMap();
  // Rectifies both raw images.
  void rectify(const cv::Mat& rawLeft, const cv::Mat& rawRight, cv::Mat& left, cv::Mat& right) const;
  // The pair of the images rectify() makes (CameraModel::rectified() of each).
  StereoCameraModel rectified() const;

  StereoCameraModel scaled(double scale) const;

  std::vector<unsigned char> serialize() const;
  static StereoCameraModel deserialize(const unsigned char* data, size_t size);  // throws FormatError

 private:
  std::string name_;
  CameraModel left_;
  CameraModel right_;
};

}  // namespace rtabmap

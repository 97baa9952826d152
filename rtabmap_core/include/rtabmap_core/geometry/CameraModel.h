#pragma once
// Pinhole camera model with distortion and rectification, as sensor_msgs/CameraInfo carries it:
// K (3x3 intrinsics), D (distortion, plumb-bob k1 k2 p1 p2 [k3 ...] or equidistant k1..k4),
// R (3x3 rectification rotation), P (3x4 projection of the rectified image), image size, and
// the local transform from the robot base frame to the camera *optical* frame (z forward,
// x right, y down).
//
// Projection functions work in the rectified image (P), which is where features and depth
// live once an image has been rectified. A model built from fx, fy, cx, cy only is already
// rectified (D = 0, R = I, P = [K | 0]).
#include <opencv2/core/mat.hpp>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

class CameraModel {
 public:
  // An invalid model (isValidForProjection() is false).
  CameraModel();
  // Rectified model. Tx = -fx * baseline for the right camera of a stereo pair.
  CameraModel(double fx, double fy, double cx, double cy,
              const Transform& localTransform = opticalRotation(), double Tx = 0.0,
              const cv::Size& imageSize = cv::Size(0, 0));
  // Full calibration. K 3x3, D 1xN (N in 4, 5, 8, 12, 14; 4 with name "equidistant" is the
  // fisheye model), R 3x3, P 3x4, all CV_64FC1; empty R or P default to identity / [K | 0].
  // Throws FormatError when a matrix has the wrong size.
  CameraModel(const std::string& name, const cv::Size& imageSize, const cv::Mat& K,
              const cv::Mat& D, const cv::Mat& R, const cv::Mat& P,
              const Transform& localTransform = opticalRotation());

  // Rotation from a robot base frame (x forward, y left, z up) to a camera optical frame
  // (z forward, x right, y down): the default local transform.
  static Transform opticalRotation();

  const std::string& name() const { return name_; }
  void setName(const std::string& name) { name_ = name; }
  // Added: the distortion model of D, in sensor_msgs/CameraInfo names: "plumb_bob" (4 or 5
  // coefficients), "rational_polynomial" (8, and OpenCV's 12/14), "equidistant" (fisheye, 4).
  // The full constructor infers it from D's size (and the name "equidistant", see above);
  // setDistortionModel() states it explicitly (throws FormatError if D does not fit it; also
  // accepts "radial-tangential" = plumb_bob and "fisheye" = equidistant, as Kalibr writes them).
  const std::string& distortionModel() const { return distortionModel_; }
  void setDistortionModel(const std::string& model);
  bool isFisheye() const { return distortionModel_ == "equidistant"; }
  bool isValidForProjection() const;       // fx, fy > 0 (from P, or K if P is empty)
  bool isValidForReprojection() const;     // and image size known
  bool isValidForRectification() const;    // K, D, R, P all present

  // Rectified intrinsics (from P).
  double fx() const;
  double fy() const;
  double cx() const;
  double cy() const;
  double Tx() const;  // P(0,3): -fx * baseline for a right stereo camera
  const cv::Mat& K_raw() const { return K_; }
  const cv::Mat& D_raw() const { return D_; }
  const cv::Mat& R() const { return R_; }
  const cv::Mat& P() const { return P_; }
  cv::Mat K() const;  // rectified K (from P)
  cv::Mat D() const;  // rectified distortion: zeros

  const cv::Size& imageSize() const { return imageSize_; }
  int imageWidth() const { return imageSize_.width; }
  int imageHeight() const { return imageSize_.height; }
  void setImageSize(const cv::Size& size) { imageSize_ = size; }
  const Transform& localTransform() const { return localTransform_; }
  void setLocalTransform(const Transform& t) { localTransform_ = t; }
  double horizontalFOV() const;  // degrees
  double verticalFOV() const;    // degrees

  // Back-projection: pixel (u, v) at depth (metres, along z) to a 3D point in the camera
  // optical frame. Returns false (and NaNs) for depth <= 0 or non-finite. Tx plays no part:
  // points are in this camera's own (rectified) optical frame, also for a right camera.
  bool project(double u, double v, double depth, double& x, double& y, double& z) const;
  // Projection of a 3D point of the optical frame to a pixel. Returns false behind the camera.
  bool reproject(double x, double y, double z, double& u, double& v) const;
  // Same, rounding to an integer pixel; false if outside the image.
  bool reproject(double x, double y, double z, int& u, int& v) const;
  // 0 <= u < width and 0 <= v < height; false when the image size is unknown.
  bool inFrame(int u, int v) const;

  // Rectification (undistortion + rotation R, projection P) with maps computed once.
  // Throws FormatError if !isValidForRectification().
  void initRectificationMap();
  bool isRectificationMapInitialized() const { return !mapX_.empty(); }
  // Rectifies an image (bilinear), or a depth image (nearest: no invented depth). Calls
  // initRectificationMap() if needed; returns the input unchanged when the model has no
  // distortion and R is identity. The lazy initialisation is guarded by a mutex (shared by
  // copies), so concurrent calls from several threads are safe. Throws FormatError if the
  // image size differs from imageSize().
  cv::Mat rectifyImage(const cv::Mat& raw, int interpolation = 1 /*cv::INTER_LINEAR*/) const;
  cv::Mat rectifyDepth(const cv::Mat& raw) const;
  // The model of the images rectifyImage() makes: the same projection (P), K from P, no
  // distortion, R identity; rectifying with it changes nothing.
  CameraModel rectified() const;
  // Its images need no rectification (no distortion, R identity, P's intrinsics those of K).
  bool isRectified() const;

  // The model of an image resized by `scale` (decimation = 1/scale), and of a region of
  // interest. Scaling follows the ROS binning convention: fx, fy, cx, cy, Tx of K and P are
  // multiplied by `scale` (no half-pixel shift), the size is rounded. scale <= 0 throws
  // std::invalid_argument.
  CameraModel scaled(double scale) const;
  CameraModel roi(const cv::Rect& roi) const;

  // Serialisation: ROS camera_info YAML (camera_calibration_parsers layout, plus a
  // `local_transform` entry {rows: 3, cols: 4, data} or a Transform::fromString string; absent
  // means opticalRotation()) and a compact binary blob for the database ("RCM" + version byte,
  // little-endian, CRC-32 at the end: any corruption or truncation throws FormatError).
  // save() returns false (and logs) if the file cannot be written.
  bool save(const std::string& yamlPath) const;
  static CameraModel load(const std::string& yamlPath);  // throws FormatError
  std::vector<unsigned char> serialize() const;
  static CameraModel deserialize(const unsigned char* data, size_t size);  // throws FormatError

 private:
  std::string name_;
  cv::Size imageSize_;
  cv::Mat K_;  // 3x3
  cv::Mat D_;  // 1xN
  cv::Mat R_;  // 3x3
  cv::Mat P_;  // 3x4
  Transform localTransform_;
  std::string distortionModel_;
  mutable cv::Mat mapX_;
  mutable cv::Mat mapY_;
  // Guards the lazy map initialisation of the const rectify functions.
  std::shared_ptr<std::mutex> mapMutex_ = std::make_shared<std::mutex>();
};

}  // namespace rtabmap

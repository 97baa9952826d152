#pragma once
// Everything one sensor frame brings to the map: images with their camera models, a laser
// scan, IMU, odometry pose and covariance, ground truth, user data, the local occupancy grid
// computed from it, and features already extracted by odometry.
//
// Images exist in two forms: raw (cv::Mat, what algorithms use) and compressed (bytes, what the
// database and ROS messages carry). compress() and uncompress() fill one form from the other;
// a node kept in the Working Memory usually holds only the compressed form.
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include <Eigen/Core>

#include <vector>

#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/IMU.h"
#include "rtabmap_core/geometry/Landmark.h"
#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/StereoCameraModel.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

// GPS fix (degrees, metres) at a stamp; stamp 0 = none.
struct GPS {
  double stamp = 0.0;
  double longitude = 0.0;
  double latitude = 0.0;
  double altitude = 0.0;
  double error = 0.0;
  double bearing = 0.0;  // North 0 -> 360 deg
};

// Local occupancy grid of a node (JFR 2019, 4.3.3): cells as points in the robot base frame,
// CV_32FC2 (2D) or CV_32FC3 (3D), one point per cell centre.
struct LocalGrid {
  cv::Mat ground;     // free cells
  cv::Mat obstacles;  // occupied cells
  cv::Mat empty;      // cells seen empty by ray tracing
  float cellSize = 0.0f;
  Eigen::Vector3f viewPoint = Eigen::Vector3f::Zero();  // sensor origin in the base frame

  bool isEmpty() const { return ground.empty() && obstacles.empty() && empty.empty(); }
};

class SensorData {
 public:
  SensorData() = default;
  // Mono or RGB-D (depth registered to rgb: CV_16UC1 mm or CV_32FC1 m). Several cameras:
  // images side by side horizontally, one model each.
  SensorData(const cv::Mat& rgb, const cv::Mat& depth, const CameraModel& model, int id = 0,
             double stamp = 0.0);
  SensorData(const cv::Mat& rgb, const cv::Mat& depth, const std::vector<CameraModel>& models,
             int id = 0, double stamp = 0.0);
  // Rectified stereo (left may be colour or grey, right grey). Several stereo cameras: left
  // images side by side horizontally, right images side by side the same way, one model each.
  SensorData(const cv::Mat& left, const cv::Mat& right, const StereoCameraModel& model,
             int id = 0, double stamp = 0.0);
  SensorData(const cv::Mat& left, const cv::Mat& right, const std::vector<StereoCameraModel>& models,
             int id = 0, double stamp = 0.0);
  // Laser only.
  SensorData(const LaserScan& scan, int id = 0, double stamp = 0.0);
  // Laser + RGB-D.
  SensorData(const LaserScan& scan, const cv::Mat& rgb, const cv::Mat& depth,
             const CameraModel& model, int id = 0, double stamp = 0.0);

  int id() const { return id_; }
  void setId(int id) { id_ = id; }
  double stamp() const { return stamp_; }
  void setStamp(double stamp) { stamp_ = stamp; }

  // --- images and cameras ---
  const cv::Mat& imageRaw() const { return imageRaw_; }
  const cv::Mat& depthOrRightRaw() const { return depthOrRightRaw_; }
  void setRGBDImage(const cv::Mat& rgb, const cv::Mat& depth, const std::vector<CameraModel>& models);
  void setStereoImage(const cv::Mat& left, const cv::Mat& right, const StereoCameraModel& model);
  // Throws FormatError when the right image is not grey, differs in size from the left, or
  // (several cameras) the image width is not a multiple of the number of cameras. Images may be
  // empty (models only, e.g. a node loaded without its images).
  void setStereoImage(const cv::Mat& left, const cv::Mat& right, const std::vector<StereoCameraModel>& models);
  const std::vector<CameraModel>& cameraModels() const { return cameraModels_; }
  const std::vector<StereoCameraModel>& stereoCameraModels() const { return stereoCameraModels_; }
  bool isStereo() const { return !stereoCameraModels_.empty(); }
  // Depth in metres at a pixel of a depth image (16UC1 mm or 32FC1 m); 0 if invalid: outside
  // the image, 0, NaN, inf, negative, and for 16UC1 also 65535 (the invalid marker of 7-Scenes
  // and others; no structured-light or ToF sensor reports 65.535 m). Other types throw
  // FormatError.
  static float depthAt(const cv::Mat& depth, int u, int v);

  // --- laser scan ---
  const LaserScan& laserScanRaw() const { return laserScanRaw_; }
  void setLaserScan(const LaserScan& scan) { laserScanRaw_ = scan; }

  // --- other sensors and metadata ---
  const IMU& imu() const { return imu_; }
  void setIMU(const IMU& imu) { imu_ = imu; }
  const GPS& gps() const { return gps_; }
  void setGPS(const GPS& gps) { gps_ = gps; }
  const cv::Mat& userDataRaw() const { return userDataRaw_; }
  void setUserData(const cv::Mat& data) { userDataRaw_ = data; }

  // Odometry pose of this frame in the odometry frame, with its 6x6 covariance (x y z roll
  // pitch yaw). Null pose = odometry unknown or lost.
  const Transform& odomPose() const { return odomPose_; }
  const Eigen::Matrix<double, 6, 6>& odomCovariance() const { return odomCovariance_; }
  void setOdom(const Transform& pose, const Eigen::Matrix<double, 6, 6>& covariance);
  const Transform& groundTruth() const { return groundTruth_; }
  void setGroundTruth(const Transform& pose) { groundTruth_ = pose; }

  // --- local occupancy grid ---
  const LocalGrid& localGrid() const { return localGrid_; }
  void setLocalGrid(const LocalGrid& grid) { localGrid_ = grid; }

  // --- landmarks seen by this frame (given with the input, or detected markers) ---
  const Landmarks& landmarks() const { return landmarks_; }
  void setLandmarks(const Landmarks& landmarks) { landmarks_ = landmarks; }

  // --- features already extracted (by odometry), reused for visual words ---
  const std::vector<cv::KeyPoint>& keypoints() const { return keypoints_; }
  const std::vector<cv::Point3f>& keypoints3D() const { return keypoints3D_; }
  const cv::Mat& descriptors() const { return descriptors_; }
  void setFeatures(const std::vector<cv::KeyPoint>& keypoints,
                   const std::vector<cv::Point3f>& keypoints3D, const cv::Mat& descriptors);

  // --- compressed form ---
  const Bytes& imageCompressed() const { return imageCompressed_; }
  const Bytes& depthOrRightCompressed() const { return depthOrRightCompressed_; }
  const Bytes& laserScanCompressed() const { return laserScanCompressed_; }
  const Bytes& userDataCompressed() const { return userDataCompressed_; }
  // Sets compressed bytes directly (loaded from the database or a ROS message). The scan's
  // metadata (format, max points, ranges, local transform) travels beside its bytes.
  void setCompressed(const Bytes& image, const Bytes& depthOrRight, const Bytes& scan,
                     const Bytes& userData);
  // Metadata of the scan, from the raw scan if there is one, else the compressed one's.
  struct ScanInfo {
    LaserScan::Format format = LaserScan::kUnknown;
    int maxPoints = 0;
    double rangeMin = 0.0;
    double rangeMax = 0.0;
    Transform localTransform = Transform::Identity();
    double angleMin = 0.0;        // beam geometry of planar scans (LaserScan::angleMin...)
    double angleMax = 0.0;
    double angleIncrement = 0.0;  // 0 = unknown
  };
  ScanInfo laserScanInfo() const;
  void setLaserScanInfo(const ScanInfo& info) { scanInfo_ = info; }

  // Fills the compressed form from the raw data (image: imageFormat, e.g. ".jpg"; depth:
  // lossless; right stereo image: png, lossless, since jpeg artefacts would bias disparities;
  // scan and user data: zlib). Images a codec cannot hold (e.g. 4 channels in jpeg, float)
  // fall back to png or zlib. Raw data is kept. Setting new images clears stale compressed
  // images.
  void compress(const std::string& imageFormat = ".jpg");
  // The two halves of compress(): the images (the image and the depth or right image on two
  // threads when parallel, Mem/CompressionParallelized), and the scan with the user data.
  void compressImages(const std::string& imageFormat, bool parallel);
  void compressScanAndUserData();
  // Fills the raw form from the compressed data, only for the parts asked. Throws FormatError
  // on corrupt bytes.
  void uncompress(bool image = true, bool depthOrRight = true, bool scan = true, bool userData = true);
  void clearRaw();
  void clearCompressed();
  // Approximate memory used by raw and compressed data, in bytes.
  size_t memoryUsed() const;

 private:
  int id_ = 0;
  double stamp_ = 0.0;
  cv::Mat imageRaw_;
  cv::Mat depthOrRightRaw_;
  std::vector<CameraModel> cameraModels_;
  std::vector<StereoCameraModel> stereoCameraModels_;
  LaserScan laserScanRaw_;
  IMU imu_;
  GPS gps_;
  cv::Mat userDataRaw_;
  Transform odomPose_;
  Eigen::Matrix<double, 6, 6> odomCovariance_ = Eigen::Matrix<double, 6, 6>::Identity();
  Transform groundTruth_;
  LocalGrid localGrid_;
  Landmarks landmarks_;
  std::vector<cv::KeyPoint> keypoints_;
  std::vector<cv::Point3f> keypoints3D_;
  cv::Mat descriptors_;

  Bytes imageCompressed_;
  Bytes depthOrRightCompressed_;
  Bytes laserScanCompressed_;
  Bytes userDataCompressed_;
  // Metadata of the compressed scan (the raw LaserScan carries its own).
  ScanInfo scanInfo_;
};

}  // namespace rtabmap

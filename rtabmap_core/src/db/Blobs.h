#pragma once
// Binary layouts of the BLOB columns of the long-term memory. Numbers are stored in the
// machine's byte order (little-endian on every platform ROS 1 runs on; checked at compile
// time in Blobs.cpp). Every decoder checks sizes and throws FormatError on a blob of the wrong
// length, so a damaged row is reported, never read out of bounds.
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include <map>
#include <string>
#include <vector>

#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"
#include "rtabmap_core/memory/Signature.h"

namespace rtabmap::db::blob {

// Transform: 12 doubles (3x4 row-major). A null transform is an empty blob (NULL column).
Bytes encodeTransform(const Transform& t);
Transform decodeTransform(const unsigned char* data, size_t size);

// Information matrix: 6 doubles when it is diagonal (the common case: 48 instead of 288
// bytes per link), else 36 doubles row-major. Exact either way.
Bytes encodeInformation(const Link::InfMatrix& information);
Link::InfMatrix decodeInformation(const unsigned char* data, size_t size);

// Velocity: 6 floats.
Bytes encodeVelocity(const Signature::Velocity& velocity);
Signature::Velocity decodeVelocity(const unsigned char* data, size_t size);

// Camera models: u8 kind (1 pinhole cameras, 2 stereo), u32 count, then per model u32 size +
// the model's own serialize() bytes. No model: empty blob.
Bytes encodeCalibration(const std::vector<CameraModel>& cameras,
                        const std::vector<StereoCameraModel>& stereo);
void decodeCalibration(const unsigned char* data, size_t size, std::vector<CameraModel>* cameras,
                       std::vector<StereoCameraModel>* stereo);

// Scan metadata: i32 format, i32 max points, f64 range min, f64 range max, 12 f64 transform.
Bytes encodeScanInfo(const SensorData::ScanInfo& info);
SensorData::ScanInfo decodeScanInfo(const unsigned char* data, size_t size);

// 3 floats (local grid view point).
Bytes encodeVector3f(const Eigen::Vector3f& v);
Eigen::Vector3f decodeVector3f(const unsigned char* data, size_t size);

// IMU: orientation (4 doubles x y z w), 3 covariances (27), angular velocity (3), linear
// acceleration (3), local transform (12). Empty IMU: empty blob.
Bytes encodeImu(const IMU& imu);
IMU decodeImu(const unsigned char* data, size_t size);

// GPS: 6 doubles. No fix (stamp 0): empty blob.
Bytes encodeGps(const GPS& gps);
GPS decodeGps(const unsigned char* data, size_t size);

// ---- Node-word features, packed per node (see Schema.cpp for why) ----

// Word id of each keypoint: count int32.
Bytes encodeWordIds(const std::vector<int>& ids);
std::vector<int> decodeWordIds(const unsigned char* data, size_t size);
// Keypoints: per keypoint x, y, size, angle, response (float32), octave, class_id (int32).
Bytes encodeKeypoints(const std::vector<cv::KeyPoint>& keypoints);
std::vector<cv::KeyPoint> decodeKeypoints(const unsigned char* data, size_t size);
// 3D points: 3 float32 each.
Bytes encodePoints(const std::vector<cv::Point3f>& points);
std::vector<cv::Point3f> decodePoints(const unsigned char* data, size_t size);
// A matrix of descriptors (or any 2D single-plane matrix): i32 OpenCV type, i32 rows, i32
// cols, then the rows packed. Empty matrix: empty blob.
Bytes encodeMatrix(const cv::Mat& matrix);
cv::Mat decodeMatrix(const unsigned char* data, size_t size);

// ---- Statistics ----

// "key value\n" lines (values printed to round-trip float exactly), zlib-compressed: keys
// repeat from node to node and compress ten-fold.
Bytes encodeStatistics(const std::map<std::string, float>& data);
std::map<std::string, float> decodeStatistics(const unsigned char* data, size_t size);
// int32 ids, zlib-compressed.
Bytes encodeIds(const std::vector<int>& ids);
std::vector<int> decodeIds(const unsigned char* data, size_t size);

}  // namespace rtabmap::db::blob

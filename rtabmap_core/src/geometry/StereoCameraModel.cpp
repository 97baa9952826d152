#include "rtabmap_core/geometry/StereoCameraModel.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <zlib.h>

#include <cmath>
#include <cstring>

#include "../codec/ByteStream.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap {

namespace {

constexpr unsigned char kMagic[3] = {'R', 'S', 'C'};
constexpr unsigned char kVersion = 1;

uint32_t crcOf(const unsigned char* data, size_t size) {
  return static_cast<uint32_t>(crc32(crc32(0L, Z_NULL, 0), data, static_cast<uInt>(size)));
}

// The right camera sits `baseline` metres along the left camera's x axis.
Transform rightOf(const Transform& left, double baseline) {
  if (left.isNull()) return left;
  return left * Transform(baseline, 0, 0, 0, 0, 0);
}

}  // namespace

StereoCameraModel::StereoCameraModel() = default;

StereoCameraModel::StereoCameraModel(const std::string& name, const CameraModel& left,
                                     const CameraModel& right)
    : name_(name), left_(left), right_(right) {}

StereoCameraModel::StereoCameraModel(double fx, double fy, double cx, double cy, double baseline,
                                     const Transform& localTransform, const cv::Size& imageSize)
    : left_(fx, fy, cx, cy, localTransform, 0.0, imageSize),
      right_(fx, fy, cx, cy, rightOf(localTransform, baseline), -fx * baseline, imageSize) {}

StereoCameraModel StereoCameraModel::fromRawCalibration(
    const std::string& name, const cv::Size& imageSize, const cv::Mat& K1, const cv::Mat& D1,
    const cv::Mat& K2, const cv::Mat& D2, const cv::Mat& R, const cv::Mat& T,
    const Transform& localTransform) {
  auto asDouble = [](const cv::Mat& m) {
    cv::Mat out;
    if (!m.empty()) m.convertTo(out, CV_64F);
    return out;
  };
  const cv::Mat k1 = asDouble(K1), d1 = asDouble(D1), k2 = asDouble(K2), d2 = asDouble(D2);
  const cv::Mat r = asDouble(R), t = asDouble(T).reshape(1, 3);
  if (k1.size() != cv::Size(3, 3) || k2.size() != cv::Size(3, 3) || r.size() != cv::Size(3, 3) ||
      t.total() != 3) {
    throw FormatError("StereoCameraModel::fromRawCalibration(\"" + name +
                      "\"): K1, K2, R must be 3x3 and T 3x1");
  }
  if (imageSize.width <= 0 || imageSize.height <= 0) {
    throw FormatError("StereoCameraModel::fromRawCalibration(\"" + name +
                      "\"): the image size is required");
  }
  cv::Mat R1, R2, P1, P2, Q;
  // Zero disparity at infinity (same cx in both images) and alpha 0: the rectified images hold
  // valid pixels only, as stereo matching wants.
  cv::stereoRectify(k1, d1, k2, d2, imageSize, r, t, R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY,
                    0.0, imageSize);
  // The models describe the *rectified* cameras: the left one is rotated by R1 from the raw
  // left camera (x_rect = R1 x_raw), so its pose in the base frame is local * R1^T.
  Transform rectLocal = localTransform;
  if (!localTransform.isNull()) {
    const cv::Mat R1t = R1.t();
    rectLocal = localTransform * Transform(R1t.at<double>(0, 0), R1t.at<double>(0, 1),
                                           R1t.at<double>(0, 2), 0, R1t.at<double>(1, 0),
                                           R1t.at<double>(1, 1), R1t.at<double>(1, 2), 0,
                                           R1t.at<double>(2, 0), R1t.at<double>(2, 1),
                                           R1t.at<double>(2, 2), 0);
  }
  StereoCameraModel model;
  model.name_ = name;
  model.left_ = CameraModel(name.empty() ? "left" : name + "_left", imageSize, k1, d1, R1, P1,
                            rectLocal);
  CameraModel right(name.empty() ? "right" : name + "_right", imageSize, k2, d2, R2, P2, rectLocal);
  model.right_ = right;
  model.right_.setLocalTransform(rightOf(rectLocal, model.baseline()));
  return model;
}

bool StereoCameraModel::isValidForProjection() const {
  return left_.isValidForProjection() && right_.isValidForProjection() && baseline() > 0.0;
}

bool StereoCameraModel::isValidForRectification() const {
  return left_.isValidForRectification() && right_.isValidForRectification();
}

double StereoCameraModel::baseline() const {
  const double fx = right_.fx();
  if (!(fx > 0.0)) return 0.0;
  return -right_.Tx() / fx;
}

void StereoCameraModel::setLocalTransform(const Transform& t) {
  left_.setLocalTransform(t);
  right_.setLocalTransform(rightOf(t, baseline()));
}

double StereoCameraModel::computeDepth(double disparity) const {
  if (!(disparity > 0.0)) return 0.0;
  return left_.fx() * baseline() / disparity;
}

double StereoCameraModel::computeDisparity(double depth) const {
  if (!(depth > 0.0)) return 0.0;
  return left_.fx() * baseline() / depth;
}

void StereoCameraModel::initRectificationMap() {
  left_.initRectificationMap();
  right_.initRectificationMap();
}

void StereoCameraModel::rectify(const cv::Mat& rawLeft, const cv::Mat& rawRight, cv::Mat& left,
                                cv::Mat& right) const {
  left = left_.rectifyImage(rawLeft);
  right = right_.rectifyImage(rawRight);
}

StereoCameraModel StereoCameraModel::rectified() const {
  return StereoCameraModel(name_, left_.rectified(), right_.rectified());
}

StereoCameraModel StereoCameraModel::scaled(double scale) const {
  return StereoCameraModel(name_, left_.scaled(scale), right_.scaled(scale));
}

std::vector<unsigned char> StereoCameraModel::serialize() const {
  std::vector<unsigned char> out;
  detail::ByteWriter w(out);
  w.raw(kMagic, 3);
  w.u8(kVersion);
  w.str(name_);
  w.bytes(left_.serialize());
  w.bytes(right_.serialize());
  w.u32(crcOf(out.data(), out.size()));
  return out;
}

StereoCameraModel StereoCameraModel::deserialize(const unsigned char* data, size_t size) {
  detail::ByteReader header(data, size, "StereoCameraModel blob");
  if (!data || size < 8 || std::memcmp(data, kMagic, 3) != 0) {
    header.fail("not a StereoCameraModel blob (" + std::to_string(size) + " bytes, bad magic)");
  }
  if (data[3] != kVersion) {
    header.fail("format version " + std::to_string(data[3]) + " is not supported (expected " +
                std::to_string(kVersion) + "; written by a newer version?)");
  }
  detail::ByteReader tail(data + size - 4, 4, "StereoCameraModel blob");
  if (tail.u32("checksum") != crcOf(data, size - 4)) {
    header.fail("checksum mismatch (corrupt or truncated)");
  }
  detail::ByteReader r(data, size - 4, "StereoCameraModel blob");
  r.skip(4, "magic");
  StereoCameraModel model;
  model.name_ = r.str("name", 4096);
  const std::vector<unsigned char> left = r.bytes("left camera");
  const std::vector<unsigned char> right = r.bytes("right camera");
  if (r.remaining() != 0) r.fail(std::to_string(r.remaining()) + " unexpected trailing bytes");
  model.left_ = CameraModel::deserialize(left.data(), left.size());
  model.right_ = CameraModel::deserialize(right.data(), right.size());
  return model;
}

}  // namespace rtabmap

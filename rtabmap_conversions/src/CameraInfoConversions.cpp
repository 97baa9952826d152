#include "rtabmap_conversions/CameraInfoConversions.h"

#include <sensor_msgs/distortion_models.h>

#include <cmath>

#include "Support.h"

namespace rtabmap_conversions {

namespace {

template <size_t N>
bool allZero(const boost::array<double, N>& values) {
  for (double v : values) {
    if (v != 0.0) return false;
  }
  return true;
}

template <size_t N>
cv::Mat matOf(const boost::array<double, N>& values, int rows, int cols) {
  cv::Mat m(rows, cols, CV_64FC1);
  for (int i = 0; i < rows * cols; ++i) m.at<double>(i / cols, i % cols) = values[i];
  return m;
}

template <size_t N>
void copyMat(const cv::Mat& m, boost::array<double, N>& out) {
  out.fill(0.0);
  if (m.empty()) return;
  for (int i = 0; i < m.rows * m.cols && i < static_cast<int>(N); ++i) out[i] = m.at<double>(i / m.cols, i % m.cols);
}

std::string describe(const sensor_msgs::CameraInfo& msg) {
  return "CameraInfo of frame '" + msg.header.frame_id + "'";
}

}  // namespace

sensor_msgs::CameraInfo cameraModelToMsg(const rtabmap::CameraModel& model, const std_msgs::Header& header) {
  sensor_msgs::CameraInfo msg;
  msg.header = header;
  msg.width = static_cast<uint32_t>(std::max(0, model.imageWidth()));
  msg.height = static_cast<uint32_t>(std::max(0, model.imageHeight()));
  msg.distortion_model = model.distortionModel().empty() ? sensor_msgs::distortion_models::PLUMB_BOB
                                                         : model.distortionModel();
  copyMat(model.K_raw(), msg.K);
  copyMat(model.R(), msg.R);
  copyMat(model.P(), msg.P);
  const cv::Mat& D = model.D_raw();
  // Fuzzing fix (fuzz/regressions/ros_camera_info): a model without distortion coefficients
  // (CameraInfo with an empty D, as many drivers publish) has an empty D_raw, whose iterators
  // divide by its zero element size (SIGFPE): no coefficients, nothing to copy.
  if (!D.empty()) msg.D.assign(D.begin<double>(), D.end<double>());
  return msg;
}

std::optional<rtabmap::CameraModel> cameraModelFromMsg(const sensor_msgs::CameraInfo& msg,
                                                       const rtabmap::Transform& localTransform,
                                                       std::string* error) {
  const std::string what = describe(msg);
  if (msg.width == 0 || msg.height == 0) {
    return detail::fail(error, what + " has no image size (" + std::to_string(msg.width) + "x" +
                                   std::to_string(msg.height) + ")");
  }
  if (!detail::allFinite(msg.K) || !detail::allFinite(msg.D) || !detail::allFinite(msg.R) ||
      !detail::allFinite(msg.P)) {
    return detail::fail(error, what + " has NaN or infinite values (K " + detail::listString(msg.K) + ", D " +
                                   detail::listString(msg.D) + ", P " + detail::listString(msg.P) + ")");
  }
  const bool kValid = msg.K[0] > 0.0 && msg.K[4] > 0.0;
  const bool pValid = msg.P[0] > 0.0 && msg.P[5] > 0.0;
  if (!kValid && !pValid) {
    return detail::fail(error, what + " has a zero focal length (K " + detail::listString(msg.K) + ", P " +
                                   detail::listString(msg.P) + "): is the camera calibrated?");
  }
  if (msg.binning_x != msg.binning_y && std::max(msg.binning_x, 1u) != std::max(msg.binning_y, 1u)) {
    return detail::fail(error, what + " has unequal binning " + std::to_string(msg.binning_x) + "x" +
                                   std::to_string(msg.binning_y) + ", which a pinhole model cannot scale");
  }
  const auto& roi = msg.roi;
  const bool hasRoi = roi.width > 0 && roi.height > 0 &&
                      !(roi.x_offset == 0 && roi.y_offset == 0 && roi.width == msg.width && roi.height == msg.height);
  if (hasRoi && (uint64_t(roi.x_offset) + roi.width > msg.width || uint64_t(roi.y_offset) + roi.height > msg.height)) {
    return detail::fail(error, what + ": region of interest " + std::to_string(roi.width) + "x" +
                                   std::to_string(roi.height) + "+" + std::to_string(roi.x_offset) + "+" +
                                   std::to_string(roi.y_offset) + " lies outside the " +
                                   std::to_string(msg.width) + "x" + std::to_string(msg.height) + " image");
  }
  try {
    // An uncalibrated rectification (all zeros) means none; a zero P means "use K".
    const cv::Mat K = kValid ? matOf(msg.K, 3, 3) : matOf(msg.P, 3, 4).colRange(0, 3).clone();
    const cv::Mat R = allZero(msg.R) ? cv::Mat() : matOf(msg.R, 3, 3);
    const cv::Mat P = pValid ? matOf(msg.P, 3, 4) : cv::Mat();
    cv::Mat D;
    if (!msg.D.empty()) D = cv::Mat(msg.D, true).reshape(1, 1);
    rtabmap::CameraModel model(msg.header.frame_id, cv::Size(int(msg.width), int(msg.height)), K, D, R, P,
                               localTransform);
    if (!msg.distortion_model.empty()) model.setDistortionModel(msg.distortion_model);
    if (hasRoi) model = model.roi(cv::Rect(int(roi.x_offset), int(roi.y_offset), int(roi.width), int(roi.height)));
    if (msg.binning_x > 1) model = model.scaled(1.0 / msg.binning_x);
    return model;
  } catch (const std::exception& e) {
    return detail::fail(error, what + ": " + e.what());
  }
}

std::optional<rtabmap::StereoCameraModel> stereoModelFromMsgs(const sensor_msgs::CameraInfo& left,
                                                              const sensor_msgs::CameraInfo& right,
                                                              const rtabmap::Transform& localTransform,
                                                              std::string* error) {
  std::optional<rtabmap::CameraModel> l = cameraModelFromMsg(left, localTransform, error);
  if (!l) return std::nullopt;
  std::optional<rtabmap::CameraModel> r = cameraModelFromMsg(right, localTransform, error);
  if (!r) return std::nullopt;
  const std::string what = "stereo pair '" + left.header.frame_id + "' / '" + right.header.frame_id + "'";
  if (l->imageSize() != r->imageSize()) {
    return detail::fail(error, what + ": left and right images differ in size (" + std::to_string(l->imageWidth()) +
                                   "x" + std::to_string(l->imageHeight()) + " vs " + std::to_string(r->imageWidth()) +
                                   "x" + std::to_string(r->imageHeight()) + ")");
  }
  if (!(r->Tx() < 0.0)) {
    return detail::fail(error, what + ": the right CameraInfo has Tx = P[3] = " + std::to_string(r->Tx()) +
                                   "; a rectified right camera has Tx = -fx * baseline < 0");
  }
  if (std::abs(l->fx() - r->fx()) > 1e-6 * l->fx() || std::abs(l->cy() - r->cy()) > 1e-3) {
    return detail::fail(error, what + ": left and right P differ (fx " + std::to_string(l->fx()) + " vs " +
                                   std::to_string(r->fx()) + ", cy " + std::to_string(l->cy()) + " vs " +
                                   std::to_string(r->cy()) + "): the images are not rectified together");
  }
  // The right rectified camera sits baseline metres along the left one's x axis.
  const double baseline = -r->Tx() / r->fx();
  if (!localTransform.isNull()) r->setLocalTransform(localTransform * rtabmap::Transform(baseline, 0, 0, 0, 0, 0));
  std::string name = left.header.frame_id;
  return rtabmap::StereoCameraModel(name, *l, *r);
}

void stereoModelToMsgs(const rtabmap::StereoCameraModel& model, const std_msgs::Header& leftHeader,
                       const std_msgs::Header& rightHeader, sensor_msgs::CameraInfo& left,
                       sensor_msgs::CameraInfo& right) {
  left = cameraModelToMsg(model.left(), leftHeader);
  right = cameraModelToMsg(model.right(), rightHeader);
}

}  // namespace rtabmap_conversions

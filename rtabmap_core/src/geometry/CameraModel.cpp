#include "rtabmap_core/geometry/CameraModel.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "../codec/ByteStream.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap {

namespace {

constexpr unsigned char kMagic[3] = {'R', 'C', 'M'};
constexpr unsigned char kVersion = 1;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string sizeString(const cv::Mat& m) {
  return std::to_string(m.rows) + "x" + std::to_string(m.cols);
}

// A CV_64FC1 deep copy (never aliasing the caller's buffer), or empty.
cv::Mat toDouble(const cv::Mat& m, const char* what) {
  if (m.empty()) return cv::Mat();
  if (m.channels() != 1) {
    throw FormatError(std::string("CameraModel: ") + what + " must be single-channel");
  }
  cv::Mat out;
  m.convertTo(out, CV_64F);
  return out;
}

bool validDistortionCount(int n) { return n == 0 || n == 4 || n == 5 || n == 8 || n == 12 || n == 14; }

std::string inferDistortionModel(int n) { return n > 5 ? "rational_polynomial" : "plumb_bob"; }

std::string canonicalDistortionModel(const std::string& model) {
  if (model == "plumb_bob" || model == "radial-tangential" || model == "radtan") return "plumb_bob";
  if (model == "rational_polynomial") return "rational_polynomial";
  if (model == "equidistant" || model == "fisheye" || model == "kannala_brandt") return "equidistant";
  return "";
}

uint32_t crcOf(const unsigned char* data, size_t size) {
  return static_cast<uint32_t>(crc32(crc32(0L, Z_NULL, 0), data, static_cast<uInt>(size)));
}

void writeMat(detail::ByteWriter& w, const cv::Mat& m) {
  w.u32(static_cast<uint32_t>(m.rows));
  w.u32(static_cast<uint32_t>(m.cols));
  for (int r = 0; r < m.rows; ++r) {
    for (int c = 0; c < m.cols; ++c) w.f64(m.at<double>(r, c));
  }
}

cv::Mat readMat(detail::ByteReader& r, const char* field) {
  const uint32_t rows = r.u32(field);
  const uint32_t cols = r.u32(field);
  if (rows > 16 || cols > 16) {
    r.fail(std::string(field) + " has an implausible size " + std::to_string(rows) + "x" +
           std::to_string(cols));
  }
  if (rows == 0 || cols == 0) return cv::Mat();
  r.need(size_t(rows) * cols * 8, field);
  cv::Mat m(static_cast<int>(rows), static_cast<int>(cols), CV_64FC1);
  for (uint32_t i = 0; i < rows; ++i) {
    for (uint32_t j = 0; j < cols; ++j) m.at<double>(i, j) = r.f64(field);
  }
  return m;
}

// --- YAML helpers (camera_calibration_parsers layout) ---

void emitMatrix(YAML::Emitter& out, const char* key, const cv::Mat& m) {
  out << YAML::Key << key << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "rows" << YAML::Value << m.rows;
  out << YAML::Key << "cols" << YAML::Value << m.cols;
  out << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int r = 0; r < m.rows; ++r) {
    for (int c = 0; c < m.cols; ++c) out << m.at<double>(r, c);
  }
  out << YAML::EndSeq << YAML::EndMap;
}

cv::Mat parseMatrix(const YAML::Node& node, const std::string& key, const std::string& path) {
  const std::string where = "CameraModel::load(" + path + "): " + key;
  if (!node.IsMap()) throw FormatError(where + " must be a map with rows, cols and data");
  const int rows = node["rows"].as<int>();
  const int cols = node["cols"].as<int>();
  const YAML::Node data = node["data"];
  if (rows < 0 || cols < 0 || rows > 16 || cols > 16 || !data.IsSequence() ||
      data.size() != static_cast<size_t>(rows) * cols) {
    throw FormatError(where + ": rows x cols (" + std::to_string(rows) + "x" +
                      std::to_string(cols) + ") does not match the " +
                      std::to_string(data.IsSequence() ? data.size() : 0) + " data values");
  }
  if (rows == 0 || cols == 0) return cv::Mat();
  cv::Mat m(rows, cols, CV_64FC1);
  for (int i = 0; i < rows * cols; ++i) m.at<double>(i / cols, i % cols) = data[i].as<double>();
  return m;
}

}  // namespace

CameraModel::CameraModel() : localTransform_(opticalRotation()) {}

CameraModel::CameraModel(double fx, double fy, double cx, double cy,
                         const Transform& localTransform, double Tx, const cv::Size& imageSize)
    : imageSize_(imageSize), localTransform_(localTransform), distortionModel_("plumb_bob") {
  K_ = (cv::Mat_<double>(3, 3) << fx, 0, cx, 0, fy, cy, 0, 0, 1);
  D_ = cv::Mat::zeros(1, 5, CV_64FC1);
  R_ = cv::Mat::eye(3, 3, CV_64FC1);
  P_ = (cv::Mat_<double>(3, 4) << fx, 0, cx, Tx, 0, fy, cy, 0, 0, 0, 1, 0);
}

CameraModel::CameraModel(const std::string& name, const cv::Size& imageSize, const cv::Mat& K,
                         const cv::Mat& D, const cv::Mat& R, const cv::Mat& P,
                         const Transform& localTransform)
    : name_(name), imageSize_(imageSize), localTransform_(localTransform) {
  K_ = toDouble(K, "K");
  if (K_.rows != 3 || K_.cols != 3) {
    throw FormatError("CameraModel \"" + name + "\": K must be 3x3, got " + sizeString(K_));
  }
  D_ = toDouble(D, "D");
  if (!D_.empty()) {
    if (D_.rows != 1 && D_.cols != 1) {
      throw FormatError("CameraModel \"" + name + "\": D must be a vector, got " + sizeString(D_));
    }
    D_ = D_.reshape(1, 1);
  }
  if (!validDistortionCount(D_.cols)) {
    throw FormatError("CameraModel \"" + name + "\": D has " + std::to_string(D_.cols) +
                      " coefficients; expected 4, 5, 8, 12 or 14");
  }
  R_ = R.empty() ? cv::Mat(cv::Mat::eye(3, 3, CV_64FC1)) : toDouble(R, "R");
  if (R_.rows != 3 || R_.cols != 3) {
    throw FormatError("CameraModel \"" + name + "\": R must be 3x3, got " + sizeString(R_));
  }
  if (P.empty()) {
    P_ = cv::Mat::zeros(3, 4, CV_64FC1);
    K_.copyTo(P_.colRange(0, 3));
  } else {
    P_ = toDouble(P, "P");
  }
  if (P_.rows != 3 || P_.cols != 4) {
    throw FormatError("CameraModel \"" + name + "\": P must be 3x4, got " + sizeString(P_));
  }
  // As documented in the header: a camera named "equidistant" with 4 coefficients is a
  // fisheye; otherwise the coefficient count decides (use setDistortionModel to be explicit).
  distortionModel_ = (name == "equidistant" && D_.cols == 4) ? "equidistant"
                                                              : inferDistortionModel(D_.cols);
}

Transform CameraModel::opticalRotation() {
  // Columns: optical x (right) = -y base, optical y (down) = -z base, optical z (fwd) = x base.
  return Transform(0, 0, 1, 0, -1, 0, 0, 0, 0, -1, 0, 0);
}

void CameraModel::setDistortionModel(const std::string& model) {
  const std::string canonical = canonicalDistortionModel(model);
  if (canonical.empty()) {
    throw FormatError("CameraModel \"" + name_ + "\": unknown distortion model \"" + model +
                      "\"; expected plumb_bob, rational_polynomial or equidistant");
  }
  const int n = D_.cols;
  const bool ok = canonical == "equidistant" ? (n == 4 || n == 0)
                                             : validDistortionCount(n);
  if (!ok) {
    throw FormatError("CameraModel \"" + name_ + "\": distortion model " + model + " does not take " +
                      std::to_string(n) + " coefficients");
  }
  distortionModel_ = canonical;
  std::lock_guard<std::mutex> lock(*mapMutex_);
  mapX_ = cv::Mat();
  mapY_ = cv::Mat();
}

bool CameraModel::isValidForProjection() const {
  return fx() > 0.0 && fy() > 0.0 && std::isfinite(cx()) && std::isfinite(cy());
}

bool CameraModel::isValidForReprojection() const {
  return isValidForProjection() && imageSize_.width > 0 && imageSize_.height > 0;
}

bool CameraModel::isValidForRectification() const {
  return !K_.empty() && !D_.empty() && !R_.empty() && !P_.empty() && K_.at<double>(0, 0) > 0.0 &&
         K_.at<double>(1, 1) > 0.0 && imageSize_.width > 0 && imageSize_.height > 0;
}

namespace {
double element(const cv::Mat& P, const cv::Mat& K, int r, int c) {
  if (!P.empty() && P.at<double>(0, 0) > 0.0) return P.at<double>(r, c);
  if (!K.empty() && c < 3) return K.at<double>(r, c);
  return 0.0;
}
}  // namespace

double CameraModel::fx() const { return element(P_, K_, 0, 0); }
double CameraModel::fy() const { return element(P_, K_, 1, 1); }
double CameraModel::cx() const { return element(P_, K_, 0, 2); }
double CameraModel::cy() const { return element(P_, K_, 1, 2); }
double CameraModel::Tx() const { return P_.empty() ? 0.0 : P_.at<double>(0, 3); }

cv::Mat CameraModel::K() const {
  if (!isValidForProjection()) return cv::Mat();
  return (cv::Mat_<double>(3, 3) << fx(), 0, cx(), 0, fy(), cy(), 0, 0, 1);
}

cv::Mat CameraModel::D() const { return cv::Mat::zeros(1, 5, CV_64FC1); }

double CameraModel::horizontalFOV() const {
  if (imageSize_.width <= 0 || fx() <= 0.0) return 0.0;
  return 2.0 * std::atan(imageSize_.width / (2.0 * fx())) * 180.0 / CV_PI;
}

double CameraModel::verticalFOV() const {
  if (imageSize_.height <= 0 || fy() <= 0.0) return 0.0;
  return 2.0 * std::atan(imageSize_.height / (2.0 * fy())) * 180.0 / CV_PI;
}

bool CameraModel::project(double u, double v, double depth, double& x, double& y, double& z) const {
  if (!(depth > 0.0) || !std::isfinite(depth) || !isValidForProjection()) {
    x = y = z = kNaN;
    return false;
  }
  // Tx is ignored on purpose: the point is in this camera's own optical frame.
  x = (u - cx()) * depth / fx();
  y = (v - cy()) * depth / fy();
  z = depth;
  return true;
}

bool CameraModel::reproject(double x, double y, double z, double& u, double& v) const {
  if (!(z > 0.0) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) ||
      !isValidForProjection()) {
    u = v = kNaN;
    return false;
  }
  u = fx() * x / z + cx();
  v = fy() * y / z + cy();
  return true;
}

bool CameraModel::reproject(double x, double y, double z, int& u, int& v) const {
  double du, dv;
  if (!reproject(x, y, z, du, dv) || std::abs(du) > 1e9 || std::abs(dv) > 1e9) return false;
  u = static_cast<int>(std::floor(du + 0.5));
  v = static_cast<int>(std::floor(dv + 0.5));
  return inFrame(u, v);
}

bool CameraModel::inFrame(int u, int v) const {
  return u >= 0 && v >= 0 && u < imageSize_.width && v < imageSize_.height;
}

namespace {
// Fixed-point maps (CV_16SC2 + interpolation table): about twice as fast in remap as float
// maps, at 1/32 pixel resolution.
void computeRectificationMaps(const CameraModel& m, cv::Mat& mapX, cv::Mat& mapY) {
  if (!m.isValidForRectification()) {
    throw FormatError("CameraModel \"" + m.name() +
                      "\": cannot rectify without K, D, R, P and the image size");
  }
  if (m.isFisheye()) {
    cv::fisheye::initUndistortRectifyMap(m.K_raw(), m.D_raw(), m.R(), m.P(), m.imageSize(),
                                         CV_16SC2, mapX, mapY);
  } else {
    cv::initUndistortRectifyMap(m.K_raw(), m.D_raw(), m.R(), m.P(), m.imageSize(), CV_16SC2,
                                mapX, mapY);
  }
}
}  // namespace

void CameraModel::initRectificationMap() {
  cv::Mat mapX, mapY;
  computeRectificationMaps(*this, mapX, mapY);
  std::lock_guard<std::mutex> lock(*mapMutex_);
  mapX_ = mapX;
  mapY_ = mapY;
}

namespace {
bool isPassThrough(const cv::Mat& K, const cv::Mat& D, const cv::Mat& R, const cv::Mat& P) {
  if (!D.empty() && cv::countNonZero(D) > 0) return false;
  if (!R.empty() && cv::norm(R, cv::Mat::eye(3, 3, CV_64FC1), cv::NORM_INF) > 1e-12) return false;
  if (!P.empty() && !K.empty() && cv::norm(P.colRange(0, 3), K, cv::NORM_INF) > 1e-9) return false;
  return true;
}
}  // namespace

cv::Mat CameraModel::rectifyImage(const cv::Mat& raw, int interpolation) const {
  if (raw.empty()) return raw;
  if (isPassThrough(K_, D_, R_, P_)) return raw;
  if (raw.cols != imageSize_.width || raw.rows != imageSize_.height) {
    throw FormatError("CameraModel \"" + name_ + "\": image of " + std::to_string(raw.cols) + "x" +
                      std::to_string(raw.rows) + " does not match the calibration size " +
                      std::to_string(imageSize_.width) + "x" + std::to_string(imageSize_.height));
  }
  cv::Mat mapX, mapY;
  {
    std::lock_guard<std::mutex> lock(*mapMutex_);
    if (mapX_.empty()) computeRectificationMaps(*this, mapX_, mapY_);
    mapX = mapX_;
    mapY = mapY_;
  }
  cv::Mat out;
  cv::remap(raw, out, mapX, mapY, interpolation, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return out;
}

cv::Mat CameraModel::rectifyDepth(const cv::Mat& raw) const {
  // Nearest neighbour: interpolating across a depth edge would invent points in mid-air.
  return rectifyImage(raw, cv::INTER_NEAREST);
}

bool CameraModel::isRectified() const { return isPassThrough(K_, D_, R_, P_); }

CameraModel CameraModel::rectified() const {
  if (isPassThrough(K_, D_, R_, P_) || !isValidForProjection()) return *this;
  CameraModel out = *this;
  out.mapX_ = cv::Mat();
  out.mapY_ = cv::Mat();
  out.mapMutex_ = std::make_shared<std::mutex>();
  out.K_ = K();
  out.D_ = D();
  out.R_ = cv::Mat::eye(3, 3, CV_64FC1);
  out.distortionModel_ = "plumb_bob";
  return out;
}

CameraModel CameraModel::scaled(double scale) const {
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    throw std::invalid_argument("CameraModel::scaled: scale must be > 0, got " + std::to_string(scale));
  }
  CameraModel out = *this;
  out.mapX_ = cv::Mat();
  out.mapY_ = cv::Mat();
  out.mapMutex_ = std::make_shared<std::mutex>();
  // ROS binning convention (fx / b, cx / b): the first two rows of K and P scale, the
  // homogeneous row does not. Tx = -fx * baseline scales with fx.
  if (!out.K_.empty()) {
    out.K_ = K_.clone();
    out.K_.rowRange(0, 2) *= scale;
  }
  if (!out.P_.empty()) {
    out.P_ = P_.clone();
    out.P_.rowRange(0, 2) *= scale;
  }
  out.R_ = R_.clone();
  out.D_ = D_.clone();
  out.imageSize_ = cv::Size(static_cast<int>(std::lround(imageSize_.width * scale)),
                            static_cast<int>(std::lround(imageSize_.height * scale)));
  return out;
}

CameraModel CameraModel::roi(const cv::Rect& roi) const {
  CameraModel out = *this;
  out.mapX_ = cv::Mat();
  out.mapY_ = cv::Mat();
  out.mapMutex_ = std::make_shared<std::mutex>();
  if (!out.K_.empty()) {
    out.K_ = K_.clone();
    out.K_.at<double>(0, 2) -= roi.x;
    out.K_.at<double>(1, 2) -= roi.y;
  }
  if (!out.P_.empty()) {
    out.P_ = P_.clone();
    out.P_.at<double>(0, 2) -= roi.x;
    out.P_.at<double>(1, 2) -= roi.y;
  }
  out.R_ = R_.clone();
  out.D_ = D_.clone();
  out.imageSize_ = roi.size();
  return out;
}

bool CameraModel::save(const std::string& yamlPath) const {
  YAML::Emitter out;
  out.SetDoublePrecision(std::numeric_limits<double>::max_digits10);
  out << YAML::BeginMap;
  out << YAML::Key << "image_width" << YAML::Value << imageSize_.width;
  out << YAML::Key << "image_height" << YAML::Value << imageSize_.height;
  out << YAML::Key << "camera_name" << YAML::Value << name_;
  emitMatrix(out, "camera_matrix", K_.empty() ? cv::Mat(cv::Mat::zeros(3, 3, CV_64FC1)) : K_);
  out << YAML::Key << "distortion_model" << YAML::Value
      << (distortionModel_.empty() ? std::string("plumb_bob") : distortionModel_);
  emitMatrix(out, "distortion_coefficients", D_.empty() ? cv::Mat(1, 0, CV_64FC1) : D_);
  emitMatrix(out, "rectification_matrix", R_.empty() ? cv::Mat(cv::Mat::eye(3, 3, CV_64FC1)) : R_);
  emitMatrix(out, "projection_matrix", P_.empty() ? cv::Mat(cv::Mat::zeros(3, 4, CV_64FC1)) : P_);
  if (!localTransform_.isNull()) {
    cv::Mat t(3, 4, CV_64FC1);
    localTransform_.toArray12(t.ptr<double>(0));
    emitMatrix(out, "local_transform", t);
  }
  out << YAML::EndMap;
  if (!out.good()) {
    RTABMAP_ERROR("CameraModel::save(" << yamlPath << "): " << out.GetLastError());
    return false;
  }
  std::ofstream file(yamlPath);
  file << out.c_str() << "\n";
  file.close();
  if (!file) {
    RTABMAP_ERROR("CameraModel::save: cannot write " << yamlPath);
    return false;
  }
  return true;
}

CameraModel CameraModel::load(const std::string& yamlPath) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yamlPath);
  } catch (const YAML::BadFile&) {
    throw FormatError("CameraModel::load: cannot open " + yamlPath);
  } catch (const YAML::Exception& e) {
    throw FormatError("CameraModel::load(" + yamlPath + "): not valid YAML: " + e.what());
  }
  if (!root.IsMap()) throw FormatError("CameraModel::load(" + yamlPath + "): not a YAML map");
  try {
    for (const char* key : {"image_width", "image_height", "camera_matrix"}) {
      if (!root[key]) {
        throw FormatError("CameraModel::load(" + yamlPath + "): missing \"" + key +
                          "\" (expected the ROS camera_info layout)");
      }
    }
    const cv::Size size(root["image_width"].as<int>(), root["image_height"].as<int>());
    const std::string name = root["camera_name"] ? root["camera_name"].as<std::string>() : "";
    const cv::Mat K = parseMatrix(root["camera_matrix"], "camera_matrix", yamlPath);
    const cv::Mat D = root["distortion_coefficients"]
                          ? parseMatrix(root["distortion_coefficients"], "distortion_coefficients", yamlPath)
                          : cv::Mat();
    const cv::Mat R = root["rectification_matrix"]
                          ? parseMatrix(root["rectification_matrix"], "rectification_matrix", yamlPath)
                          : cv::Mat();
    cv::Mat P = root["projection_matrix"]
                    ? parseMatrix(root["projection_matrix"], "projection_matrix", yamlPath)
                    : cv::Mat();
    // An uncalibrated camera_info has an all-zero P: fall back to [K | 0].
    if (!P.empty() && cv::countNonZero(P) == 0) P = cv::Mat();
    Transform local = opticalRotation();
    if (const YAML::Node lt = root["local_transform"]) {
      if (lt.IsScalar()) {
        local = Transform::fromString(lt.as<std::string>());
      } else {
        const cv::Mat m = parseMatrix(lt, "local_transform", yamlPath);
        if ((m.rows != 3 && m.rows != 4) || m.cols != 4) {
          throw FormatError("CameraModel::load(" + yamlPath + "): local_transform must be 3x4 or 4x4");
        }
        local = Transform::fromArray12(m.ptr<double>(0));
      }
    }
    CameraModel model(name, size, K, D, R, P, local);
    if (const YAML::Node dm = root["distortion_model"]) {
      const std::string dmName = dm.as<std::string>();
      // Empty D has no model worth checking; otherwise the file's word is the law.
      if (!model.D_.empty()) model.setDistortionModel(dmName);
    }
    return model;
  } catch (const YAML::Exception& e) {
    throw FormatError("CameraModel::load(" + yamlPath + "): bad value: " + e.what());
  } catch (const FormatError& e) {
    const std::string what = e.what();
    if (what.find(yamlPath) != std::string::npos) throw;
    throw FormatError("CameraModel::load(" + yamlPath + "): " + what);
  }
}

std::vector<unsigned char> CameraModel::serialize() const {
  std::vector<unsigned char> out;
  detail::ByteWriter w(out);
  w.raw(kMagic, 3);
  w.u8(kVersion);
  w.str(name_);
  w.str(distortionModel_);
  w.i32(imageSize_.width);
  w.i32(imageSize_.height);
  writeMat(w, K_);
  writeMat(w, D_);
  writeMat(w, R_);
  writeMat(w, P_);
  w.u8(localTransform_.isNull() ? 0 : 1);
  if (!localTransform_.isNull()) {
    double a[12];
    localTransform_.toArray12(a);
    for (double v : a) w.f64(v);
  }
  // A checksum: a flipped bit inside a double would otherwise pass every structural check.
  w.u32(crcOf(out.data(), out.size()));
  return out;
}

CameraModel CameraModel::deserialize(const unsigned char* data, size_t size) {
  detail::ByteReader header(data, size, "CameraModel blob");
  if (!data || size < 8 || std::memcmp(data, kMagic, 3) != 0) {
    header.fail("not a CameraModel blob (" + std::to_string(size) + " bytes, bad magic)");
  }
  if (data[3] != kVersion) {
    header.fail("format version " + std::to_string(data[3]) + " is not supported (expected " +
                std::to_string(kVersion) + "; written by a newer version?)");
  }
  detail::ByteReader tail(data + size - 4, 4, "CameraModel blob");
  if (tail.u32("checksum") != crcOf(data, size - 4)) {
    header.fail("checksum mismatch (corrupt or truncated)");
  }
  detail::ByteReader r(data, size - 4, "CameraModel blob");
  r.skip(4, "magic");
  CameraModel m;
  m.name_ = r.str("name", 4096);
  m.distortionModel_ = r.str("distortion model", 64);
  m.imageSize_.width = r.i32("width");
  m.imageSize_.height = r.i32("height");
  m.K_ = readMat(r, "K");
  m.D_ = readMat(r, "D");
  m.R_ = readMat(r, "R");
  m.P_ = readMat(r, "P");
  const uint8_t hasTransform = r.u8("local transform flag");
  if (hasTransform > 1) r.fail("bad local transform flag");
  if (hasTransform) {
    double a[12];
    for (double& v : a) v = r.f64("local transform");
    m.localTransform_ = Transform::fromArray12(a);
  } else {
    m.localTransform_ = Transform();
  }
  if (r.remaining() != 0) r.fail(std::to_string(r.remaining()) + " unexpected trailing bytes");
  // Same shape rules as the constructor.
  if ((!m.K_.empty() && (m.K_.rows != 3 || m.K_.cols != 3)) ||
      (!m.R_.empty() && (m.R_.rows != 3 || m.R_.cols != 3)) ||
      (!m.P_.empty() && (m.P_.rows != 3 || m.P_.cols != 4)) ||
      (!m.D_.empty() && (m.D_.rows != 1 || !validDistortionCount(m.D_.cols))) ||
      m.imageSize_.width < 0 || m.imageSize_.height < 0) {
    r.fail("matrix shapes or image size are invalid");
  }
  if (!m.distortionModel_.empty() && canonicalDistortionModel(m.distortionModel_) != m.distortionModel_) {
    r.fail("unknown distortion model \"" + m.distortionModel_ + "\"");
  }
  return m;
}

}  // namespace rtabmap

#include "rtabmap_core/geometry/StereoCameraModel.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "common/TestData.h"
#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"

using rtabmap::CameraModel;
using rtabmap::FormatError;
using rtabmap::StereoCameraModel;
using rtabmap::Transform;

namespace {

struct EurocCamera {
  cv::Mat K, D;
  cv::Size size;
  Transform T_BS;  // body -> sensor
};

EurocCamera readEurocCamera(const std::string& path) {
  cv::FileStorage fs(path, cv::FileStorage::READ);
  EXPECT_TRUE(fs.isOpened()) << path;
  std::vector<double> intr, dist, tbs;
  std::vector<int> res;
  fs["intrinsics"] >> intr;
  fs["distortion_coefficients"] >> dist;
  fs["resolution"] >> res;
  fs["T_BS"]["data"] >> tbs;
  EXPECT_EQ(intr.size(), 4u);
  EXPECT_EQ(dist.size(), 4u);
  EXPECT_EQ(tbs.size(), 16u);
  EXPECT_EQ(res.size(), 2u);
  EurocCamera c;
  c.K = (cv::Mat_<double>(3, 3) << intr[0], 0, intr[2], 0, intr[1], intr[3], 0, 0, 1);
  c.D = cv::Mat(dist, true).reshape(1, 1);
  c.size = cv::Size(res[0], res[1]);
  c.T_BS = Transform::fromArray12(tbs.data());
  return c;
}

cv::Mat readGrey(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  const rtabmap::Bytes bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  return rtabmap::codec::uncompressImage(bytes);
}

StereoCameraModel eurocStereo(const std::string& dir, EurocCamera* cam0Out = nullptr,
                              EurocCamera* cam1Out = nullptr) {
  const EurocCamera c0 = readEurocCamera(dir + "/cam0/sensor.yaml");
  const EurocCamera c1 = readEurocCamera(dir + "/cam1/sensor.yaml");
  // Pose of the left camera in the right camera frame: x_right = R x_left + T.
  const Transform rightFromLeft = c1.T_BS.inverse() * c0.T_BS;
  cv::Mat R(3, 3, CV_64FC1), T(3, 1, CV_64FC1);
  const Eigen::Matrix4d m = rightFromLeft.toMatrix4d();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) R.at<double>(i, j) = m(i, j);
    T.at<double>(i) = m(i, 3);
  }
  if (cam0Out) *cam0Out = c0;
  if (cam1Out) *cam1Out = c1;
  return StereoCameraModel::fromRawCalibration("euroc", c0.size, c0.K, c0.D, c1.K, c1.D, R, T, c0.T_BS);
}

// Minimum eigenvalue of the structure tensor over a (2r+1)^2 window: corner strength.
double cornerScore(const cv::Mat& img, int u, int v, int r) {
  double sxx = 0, syy = 0, sxy = 0;
  for (int y = v - r; y <= v + r; ++y) {
    for (int x = u - r; x <= u + r; ++x) {
      const double gx = 0.5 * (img.at<uchar>(y, x + 1) - img.at<uchar>(y, x - 1));
      const double gy = 0.5 * (img.at<uchar>(y + 1, x) - img.at<uchar>(y - 1, x));
      sxx += gx * gx;
      syy += gy * gy;
      sxy += gx * gy;
    }
  }
  const double tr = sxx + syy, det = sxx * syy - sxy * sxy;
  return tr / 2 - std::sqrt(std::max(0.0, tr * tr / 4 - det));
}

double ncc(const cv::Mat& a, int ua, int va, const cv::Mat& b, int ub, int vb, int r) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  const int n = (2 * r + 1) * (2 * r + 1);
  for (int dy = -r; dy <= r; ++dy) {
    const uchar* pa = a.ptr<uchar>(va + dy);
    const uchar* pb = b.ptr<uchar>(vb + dy);
    for (int dx = -r; dx <= r; ++dx) {
      const double x = pa[ua + dx], y = pb[ub + dx];
      sa += x;
      sb += y;
      saa += x * x;
      sbb += y * y;
      sab += x * y;
    }
  }
  const double cov = sab - sa * sb / n, va2 = saa - sa * sa / n, vb2 = sbb - sb * sb / n;
  return (va2 > 1e-9 && vb2 > 1e-9) ? cov / std::sqrt(va2 * vb2) : -1.0;
}

// Vertical offsets (right row - left row, sub-pixel) of left corners matched in the right image
// by normalised cross-correlation over disparities [0, maxDisparity] and rows +-rowSearch.
std::vector<double> rowOffsets(const cv::Mat& left, const cv::Mat& right, int maxDisparity, int rowSearch) {
  const int r = 7, cell = 40, margin = r + rowSearch + 2;
  std::vector<double> offsets;
  for (int cv0 = margin; cv0 + cell < left.rows - margin; cv0 += cell) {
    for (int cu0 = margin + maxDisparity / 2; cu0 + cell < left.cols - margin; cu0 += cell) {
      // Strongest corner of the cell.
      double best = 0;
      int bu = -1, bv = -1;
      for (int v = cv0; v < cv0 + cell; v += 2) {
        for (int u = cu0; u < cu0 + cell; u += 2) {
          const double s = cornerScore(left, u, v, 3);
          if (s > best) {
            best = s;
            bu = u;
            bv = v;
          }
        }
      }
      if (best < 200) continue;  // flat cell
      // Search the right image.
      double top = -2, second = -2;
      int tu = 0, tv = 0;
      for (int v = bv - rowSearch; v <= bv + rowSearch; ++v) {
        for (int d = 0; d <= maxDisparity; ++d) {
          const int u = bu - d;
          if (u - r < 0) break;
          const double s = ncc(left, bu, bv, right, u, v, r);
          if (s > top) {
            if (std::abs(u - tu) > 2 || std::abs(v - tv) > 2) second = top;
            top = s;
            tu = u;
            tv = v;
          } else if (s > second && (std::abs(u - tu) > 2 || std::abs(v - tv) > 2)) {
            second = s;
          }
        }
      }
      if (top < 0.9 || second > top - 0.05) continue;  // weak or ambiguous
      if (tv <= bv - rowSearch || tv >= bv + rowSearch) continue;  // on the search border
      // Parabola through the scores of the rows above and below.
      const double sm = ncc(left, bu, bv, right, tu, tv - 1, r);
      const double sp = ncc(left, bu, bv, right, tu, tv + 1, r);
      const double denom = sm - 2 * top + sp;
      const double sub = std::abs(denom) > 1e-12 ? 0.5 * (sm - sp) / denom : 0.0;
      offsets.push_back(tv + std::clamp(sub, -0.5, 0.5) - bv);
    }
  }
  return offsets;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

TEST(StereoCameraModel, FromIntrinsics) {
  const StereoCameraModel s(435.2, 435.2, 367.4, 252.2, 0.11, CameraModel::opticalRotation(), cv::Size(752, 480));
  EXPECT_TRUE(s.isValidForProjection());
  EXPECT_NEAR(s.baseline(), 0.11, 1e-12);
  EXPECT_DOUBLE_EQ(s.left().Tx(), 0);
  EXPECT_NEAR(s.right().Tx(), -435.2 * 0.11, 1e-12);
  EXPECT_DOUBLE_EQ(s.left().fx(), s.right().fx());
  EXPECT_DOUBLE_EQ(s.left().cx(), s.right().cx());
  // depth <-> disparity
  EXPECT_NEAR(s.computeDepth(435.2 * 0.11 / 2.0), 2.0, 1e-12);
  EXPECT_NEAR(s.computeDisparity(2.0), 435.2 * 0.11 / 2.0, 1e-12);
  EXPECT_EQ(s.computeDepth(0), 0);
  EXPECT_EQ(s.computeDepth(-3), 0);
  EXPECT_EQ(s.computeDisparity(0), 0);
  for (double d : {0.3, 1.0, 7.0, 40.0}) EXPECT_NEAR(s.computeDepth(s.computeDisparity(d)), d, 1e-9);
  // The right camera is baseline metres along the left camera's x axis.
  const Eigen::Vector3d offset = s.right().localTransform().translation() - s.localTransform().translation();
  EXPECT_NEAR(offset.norm(), 0.11, 1e-12);
  EXPECT_LE((s.localTransform().rotationMatrix().col(0) * 0.11 - offset).norm(), 1e-12);
  // setLocalTransform moves both.
  StereoCameraModel moved = s;
  moved.setLocalTransform(Transform(1, 2, 3, 0, 0, 0));
  EXPECT_EQ(moved.localTransform(), Transform(1, 2, 3, 0, 0, 0));
  EXPECT_NEAR(moved.right().localTransform().x(), 1.11, 1e-12);
  // Invalid models.
  EXPECT_FALSE(StereoCameraModel().isValidForProjection());
  EXPECT_FALSE(StereoCameraModel(435, 435, 367, 252, 0.0).isValidForProjection());
  EXPECT_FALSE(StereoCameraModel(435, 435, 367, 252, -0.1).isValidForProjection());
}

TEST(StereoCameraModel, FromRectifiedCameraInfos) {
  const CameraModel left("left", cv::Size(640, 480), (cv::Mat_<double>(3, 3) << 500, 0, 320, 0, 500, 240, 0, 0, 1),
                         cv::Mat::zeros(1, 5, CV_64FC1), cv::Mat(),
                         (cv::Mat_<double>(3, 4) << 480, 0, 322, 0, 0, 480, 241, 0, 0, 0, 1, 0));
  const CameraModel right("right", cv::Size(640, 480), (cv::Mat_<double>(3, 3) << 500, 0, 320, 0, 500, 240, 0, 0, 1),
                          cv::Mat::zeros(1, 5, CV_64FC1), cv::Mat(),
                          (cv::Mat_<double>(3, 4) << 480, 0, 322, -480 * 0.075, 0, 480, 241, 0, 0, 0, 1, 0));
  const StereoCameraModel s("zed", left, right);
  EXPECT_EQ(s.name(), "zed");
  EXPECT_NEAR(s.baseline(), 0.075, 1e-12);
  EXPECT_TRUE(s.isValidForProjection());
  EXPECT_TRUE(s.isValidForRectification());
  const StereoCameraModel h = s.scaled(0.5);
  EXPECT_NEAR(h.baseline(), 0.075, 1e-12);  // baseline is metric: unchanged by scaling
  EXPECT_DOUBLE_EQ(h.left().fx(), 240);
  EXPECT_EQ(h.left().imageSize(), cv::Size(320, 240));
}

TEST(StereoCameraModel, BinaryRoundTrip) {
  const StereoCameraModel s(435.2, 436.1, 367.4, 252.2, 0.11, Transform(0.1, 0.2, 0.3, 0.4, 0.5, 0.6),
                            cv::Size(752, 480));
  const std::vector<unsigned char> blob = s.serialize();
  const StereoCameraModel back = StereoCameraModel::deserialize(blob.data(), blob.size());
  EXPECT_EQ(back.name(), s.name());
  EXPECT_DOUBLE_EQ(back.baseline(), s.baseline());
  EXPECT_EQ(back.localTransform(), s.localTransform());
  EXPECT_EQ(back.right().localTransform(), s.right().localTransform());
  EXPECT_EQ(back.serialize(), blob);
  for (size_t n = 0; n < blob.size(); n += 3) {
    EXPECT_THROW(StereoCameraModel::deserialize(blob.data(), n), FormatError) << n;
  }
  for (size_t i = 0; i < blob.size(); i += 5) {
    std::vector<unsigned char> bad = blob;
    bad[i] ^= 0x01;
    EXPECT_THROW(StereoCameraModel::deserialize(bad.data(), bad.size()), FormatError) << i;
  }
  // A camera blob is not a stereo blob.
  const std::vector<unsigned char> mono = s.left().serialize();
  EXPECT_THROW(StereoCameraModel::deserialize(mono.data(), mono.size()), FormatError);
}

TEST(StereoCameraModel, FromRawCalibrationSynthetic) {
  // Two identical cameras 12 cm apart with a slight relative rotation.
  const cv::Mat K = (cv::Mat_<double>(3, 3) << 450, 0, 370, 0, 452, 245, 0, 0, 1);
  const cv::Mat D = (cv::Mat_<double>(1, 4) << -0.28, 0.07, 0.0002, 0.00002);
  const Transform rightFromLeft = Transform(-0.12, 0.001, 0.0005, 0.004, -0.006, 0.002);
  const Eigen::Matrix4d m = rightFromLeft.toMatrix4d();
  cv::Mat R(3, 3, CV_64FC1), T(3, 1, CV_64FC1);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) R.at<double>(i, j) = m(i, j);
    T.at<double>(i) = m(i, 3);
  }
  const StereoCameraModel s = StereoCameraModel::fromRawCalibration(
      "synthetic", cv::Size(752, 480), K, D, K, D, R, T, CameraModel::opticalRotation());
  EXPECT_TRUE(s.isValidForProjection());
  EXPECT_TRUE(s.isValidForRectification());
  EXPECT_NEAR(s.baseline(), rightFromLeft.getNorm(), 1e-9);
  EXPECT_EQ(s.left().name(), "synthetic_left");
  EXPECT_EQ(s.right().name(), "synthetic_right");
  // CALIB_ZERO_DISPARITY: same principal point in both rectified images.
  EXPECT_DOUBLE_EQ(s.left().cx(), s.right().cx());
  EXPECT_DOUBLE_EQ(s.left().cy(), s.right().cy());
  EXPECT_DOUBLE_EQ(s.left().fx(), s.right().fx());
  // The right rectified camera sits exactly along the left rectified camera's x axis, and that
  // agrees with the raw geometry: right raw camera = left raw * rightFromLeft^-1.
  const Transform rawRight = CameraModel::opticalRotation() * rightFromLeft.inverse();
  EXPECT_LE((s.right().localTransform().translation() - rawRight.translation()).norm(), 1e-9);
  StereoCameraModel copy = s;
  copy.initRectificationMap();
  cv::Mat l(480, 752, CV_8UC1, cv::Scalar(100)), r(480, 752, CV_8UC1, cv::Scalar(100)), lo, ro;
  copy.rectify(l, r, lo, ro);
  EXPECT_EQ(lo.size(), l.size());
  EXPECT_EQ(ro.size(), r.size());
  EXPECT_THROW(StereoCameraModel::fromRawCalibration("bad", cv::Size(752, 480), K, D, K, D,
                                                      cv::Mat::eye(2, 2, CV_64FC1), T, Transform::Identity()),
               FormatError);
  EXPECT_THROW(StereoCameraModel::fromRawCalibration("bad", cv::Size(0, 0), K, D, K, D, R, T,
                                                      Transform::Identity()),
               FormatError);
}

TEST(StereoCameraModel, EurocCalibrationBaseline) {
  RTABMAP_REQUIRE_DATA(dir, "euroc_v1_01_micro/mav0");
  EurocCamera c0, c1;
  const StereoCameraModel s = eurocStereo(dir, &c0, &c1);
  EXPECT_EQ(c0.size, cv::Size(752, 480));
  EXPECT_NEAR(s.baseline(), 0.110, 0.002);
  EXPECT_TRUE(s.isValidForProjection());
  EXPECT_TRUE(s.isValidForRectification());
  // Rectified frames: left = T_BS0 * R1^T, right = T_BS1 * R2^T; the right one computed from
  // the left and the baseline lands on the right raw camera's position.
  EXPECT_LE((s.localTransform().translation() - c0.T_BS.translation()).norm(), 1e-12);
  EXPECT_LE((s.right().localTransform().translation() - c1.T_BS.translation()).norm(), 1e-6);
  // Rectification only rotates a little.
  EXPECT_LT((c0.T_BS.inverse() * s.localTransform()).getAngle(), 0.05);
  // The blob survives serialisation and rectifies identically.
  const std::vector<unsigned char> blob = s.serialize();
  const StereoCameraModel back = StereoCameraModel::deserialize(blob.data(), blob.size());
  EXPECT_DOUBLE_EQ(back.baseline(), s.baseline());
  EXPECT_EQ(back.left().distortionModel(), "plumb_bob");
}

TEST(StereoCameraModel, EurocRectifiedPairIsRowAligned) {
  RTABMAP_REQUIRE_DATA(dir, "euroc_v1_01_micro/mav0");
  StereoCameraModel s = eurocStereo(dir);
  s.initRectificationMap();
  // Pairs with the same timestamp name in cam0 and cam1.
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir + "/cam0/data")) {
    const std::string name = e.path().filename().string();
    if (e.path().extension() == ".png" && std::filesystem::exists(dir + "/cam1/data/" + name)) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  ASSERT_GE(names.size(), 3u);
  std::vector<double> rectified, raw;
  for (size_t i = 0; i < names.size() && i < 30; i += 10) {
    const cv::Mat rawLeft = readGrey(dir + "/cam0/data/" + names[i]);
    const cv::Mat rawRight = readGrey(dir + "/cam1/data/" + names[i]);
    ASSERT_EQ(rawLeft.type(), CV_8UC1);
    ASSERT_EQ(rawLeft.size(), cv::Size(752, 480));
    cv::Mat left, right;
    s.rectify(rawLeft, rawRight, left, right);
    const std::vector<double> r = rowOffsets(left, right, 80, 8);
    rectified.insert(rectified.end(), r.begin(), r.end());
    const std::vector<double> r0 = rowOffsets(rawLeft, rawRight, 80, 8);
    raw.insert(raw.end(), r0.begin(), r0.end());
  }
  ASSERT_GE(rectified.size(), 30u) << "too few matches to judge";
  std::vector<double> absOffsets;
  for (double o : rectified) absOffsets.push_back(std::abs(o));
  const double med = median(absOffsets);
  const double medRaw = raw.empty() ? 0 : median(raw);
  EXPECT_LT(med, 1.0) << rectified.size() << " matches; raw images: median row offset " << medRaw;
  EXPECT_LT(std::abs(median(rectified)), 0.5);
  RecordProperty("matches", static_cast<int>(rectified.size()));
  std::cout << "EuRoC rectified: " << rectified.size() << " matches, median |row offset| " << med
            << " px (raw images: median row offset " << medRaw << " px over " << raw.size() << ")\n";
}

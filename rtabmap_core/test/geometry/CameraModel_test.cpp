#include "rtabmap_core/geometry/CameraModel.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <cmath>
#include <fstream>
#include <thread>

#include "common/TestData.h"
#include "rtabmap_core/common/Error.h"

using rtabmap::CameraModel;
using rtabmap::FormatError;
using rtabmap::Transform;

namespace {

const cv::Size kSize(640, 480);

cv::Mat makeK(double fx, double fy, double cx, double cy) {
  return (cv::Mat_<double>(3, 3) << fx, 0, cx, 0, fy, cy, 0, 0, 1);
}

cv::Mat makeP(double fx, double fy, double cx, double cy, double Tx = 0) {
  return (cv::Mat_<double>(3, 4) << fx, 0, cx, Tx, 0, fy, cy, 0, 0, 0, 1, 0);
}

cv::Mat rotationMat(double roll, double pitch, double yaw) {
  const Eigen::Matrix3d r = Transform(0, 0, 0, roll, pitch, yaw).rotationMatrix();
  cv::Mat m(3, 3, CV_64FC1);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.at<double>(i, j) = r(i, j);
  return m;
}

// The distortion models written out independently of OpenCV: normalised raw coordinates
// (a, b) -> distorted normalised coordinates.
cv::Point2d distortPlumbBob(const cv::Mat& D, double a, double b) {
  double k[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  for (int i = 0; i < D.cols && i < 8; ++i) k[i] = D.at<double>(0, i);
  const double k1 = k[0], k2 = k[1], p1 = k[2], p2 = k[3], k3 = k[4], k4 = k[5], k5 = k[6], k6 = k[7];
  const double r2 = a * a + b * b, r4 = r2 * r2, r6 = r4 * r2;
  const double radial = (1 + k1 * r2 + k2 * r4 + k3 * r6) / (1 + k4 * r2 + k5 * r4 + k6 * r6);
  return {a * radial + 2 * p1 * a * b + p2 * (r2 + 2 * a * a),
          b * radial + p1 * (r2 + 2 * b * b) + 2 * p2 * a * b};
}

cv::Point2d distortEquidistant(const cv::Mat& D, double a, double b) {
  const double r = std::sqrt(a * a + b * b);
  if (r < 1e-12) return {a, b};
  const double t = std::atan(r), t2 = t * t;
  const double td = t * (1 + D.at<double>(0, 0) * t2 + D.at<double>(0, 1) * t2 * t2 +
                         D.at<double>(0, 2) * t2 * t2 * t2 + D.at<double>(0, 3) * t2 * t2 * t2 * t2);
  return {a * td / r, b * td / r};
}

// Where the raw camera sees the ray of rectified pixel (ur, vr).
cv::Point2d rawPixelOf(const CameraModel& m, double ur, double vr) {
  const cv::Mat P = m.P();
  const cv::Mat K = m.K_raw();
  // Rectified ray, then back to the raw camera frame with R^T.
  cv::Mat ray = (cv::Mat_<double>(3, 1) << (ur - P.at<double>(0, 2)) / P.at<double>(0, 0),
                 (vr - P.at<double>(1, 2)) / P.at<double>(1, 1), 1.0);
  cv::Mat raw = m.R().t() * ray;
  const double a = raw.at<double>(0) / raw.at<double>(2), b = raw.at<double>(1) / raw.at<double>(2);
  const cv::Point2d d = m.isFisheye() ? distortEquidistant(m.D_raw(), a, b)
                                      : distortPlumbBob(m.D_raw(), a, b);
  return {K.at<double>(0, 0) * d.x + K.at<double>(0, 2), K.at<double>(1, 1) * d.y + K.at<double>(1, 2)};
}

// Inverse of rawPixelOf for plumb bob, by fixed-point iteration (moderate distortion).
cv::Point2d rectifiedPixelOf(const CameraModel& m, double u, double v) {
  const cv::Mat K = m.K_raw();
  const double xd = (u - K.at<double>(0, 2)) / K.at<double>(0, 0);
  const double yd = (v - K.at<double>(1, 2)) / K.at<double>(1, 1);
  double a = xd, b = yd;
  for (int i = 0; i < 50; ++i) {
    const cv::Point2d d = distortPlumbBob(m.D_raw(), a, b);
    a += xd - d.x;
    b += yd - d.y;
  }
  cv::Mat ray = m.R() * (cv::Mat_<double>(3, 1) << a, b, 1.0);
  const cv::Mat P = m.P();
  return {P.at<double>(0, 0) * ray.at<double>(0) / ray.at<double>(2) + P.at<double>(0, 2),
          P.at<double>(1, 1) * ray.at<double>(1) / ray.at<double>(2) + P.at<double>(1, 2)};
}

// Raw image with small Gaussian blobs at the raw pixels of the given rectified targets.
cv::Mat renderBlobs(const CameraModel& m, const std::vector<cv::Point2d>& rectTargets) {
  cv::Mat img(m.imageSize(), CV_32FC1, cv::Scalar(0));
  const double sigma = 1.5;
  for (const cv::Point2d& t : rectTargets) {
    const cv::Point2d c = rawPixelOf(m, t.x, t.y);
    for (int v = std::max(0, int(c.y) - 8); v <= std::min(img.rows - 1, int(c.y) + 8); ++v) {
      for (int u = std::max(0, int(c.x) - 8); u <= std::min(img.cols - 1, int(c.x) + 8); ++u) {
        const double d2 = (u - c.x) * (u - c.x) + (v - c.y) * (v - c.y);
        img.at<float>(v, u) += static_cast<float>(250.0 * std::exp(-d2 / (2 * sigma * sigma)));
      }
    }
  }
  cv::Mat out;
  img.convertTo(out, CV_8UC1);
  return out;
}

cv::Point2d centroid(const cv::Mat& img, const cv::Point2d& around, int radius) {
  double sw = 0, su = 0, sv = 0;
  for (int v = int(around.y) - radius; v <= int(around.y) + radius; ++v) {
    for (int u = int(around.x) - radius; u <= int(around.x) + radius; ++u) {
      if (u < 0 || v < 0 || u >= img.cols || v >= img.rows) continue;
      const double w = img.at<uchar>(v, u);
      sw += w;
      su += w * u;
      sv += w * v;
    }
  }
  return sw > 0 ? cv::Point2d(su / sw, sv / sw) : cv::Point2d(-1e9, -1e9);
}

// Rectifies blobs and checks each lands where the rectified model says, within 0.5 px.
void checkBlobsMapBack(const CameraModel& m) {
  std::vector<cv::Point2d> targets;
  for (int v = 60; v <= 420; v += 60) {
    for (int u = 60; u <= 580; u += 65) {
      const cv::Point2d raw = rawPixelOf(m, u, v);
      if (raw.x > 10 && raw.y > 10 && raw.x < m.imageWidth() - 10 && raw.y < m.imageHeight() - 10) {
        targets.emplace_back(u, v);
      }
    }
  }
  ASSERT_GT(targets.size(), 20u);
  const cv::Mat raw = renderBlobs(m, targets);
  const cv::Mat rect = m.rectifyImage(raw);
  ASSERT_EQ(rect.size(), raw.size());
  ASSERT_EQ(rect.type(), raw.type());
  double worst = 0;
  for (const cv::Point2d& t : targets) {
    const cv::Point2d c = centroid(rect, t, 6);
    worst = std::max(worst, std::hypot(c.x - t.x, c.y - t.y));
  }
  EXPECT_LT(worst, 0.5) << "D=" << m.D_raw() << " model " << m.distortionModel();
}

CameraModel distortedModel(const cv::Mat& D, const cv::Mat& R = cv::Mat(),
                           const std::string& name = "test") {
  return CameraModel(name, kSize, makeK(400, 410, 321.5, 238.7), D, R,
                     makeP(380, 380, 320, 240), Transform(0.1, 0, 0.5, -M_PI / 2, 0, -M_PI / 2));
}

bool identical(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         (a.empty() || cv::norm(a, b, cv::NORM_INF) == 0.0);
}

void expectSameModel(const CameraModel& a, const CameraModel& b) {
  EXPECT_EQ(a.name(), b.name());
  EXPECT_EQ(a.imageSize(), b.imageSize());
  EXPECT_EQ(a.distortionModel(), b.distortionModel());
  EXPECT_TRUE(identical(a.K_raw(), b.K_raw())) << a.K_raw() << b.K_raw();
  EXPECT_TRUE(identical(a.D_raw(), b.D_raw())) << a.D_raw() << b.D_raw();
  EXPECT_TRUE(identical(a.R(), b.R()));
  EXPECT_TRUE(identical(a.P(), b.P()));
  EXPECT_EQ(a.localTransform(), b.localTransform());
}

}  // namespace

TEST(CameraModel, DefaultIsInvalid) {
  const CameraModel m;
  EXPECT_FALSE(m.isValidForProjection());
  EXPECT_FALSE(m.isValidForReprojection());
  EXPECT_FALSE(m.isValidForRectification());
  double x, y, z;
  EXPECT_FALSE(m.project(1, 1, 1, x, y, z));
  EXPECT_TRUE(std::isnan(x));
  EXPECT_THROW(CameraModel().initRectificationMap(), FormatError);
}

TEST(CameraModel, IntrinsicsConstructor) {
  const CameraModel m(525, 526, 319.5, 239.5, CameraModel::opticalRotation(), 0.0, kSize);
  EXPECT_TRUE(m.isValidForProjection());
  EXPECT_TRUE(m.isValidForReprojection());
  EXPECT_TRUE(m.isValidForRectification());
  EXPECT_DOUBLE_EQ(m.fx(), 525);
  EXPECT_DOUBLE_EQ(m.fy(), 526);
  EXPECT_DOUBLE_EQ(m.cx(), 319.5);
  EXPECT_DOUBLE_EQ(m.cy(), 239.5);
  EXPECT_DOUBLE_EQ(m.Tx(), 0);
  EXPECT_EQ(m.imageWidth(), 640);
  EXPECT_EQ(m.imageHeight(), 480);
  EXPECT_TRUE(identical(m.K(), makeK(525, 526, 319.5, 239.5)));
  EXPECT_TRUE(identical(m.P(), makeP(525, 526, 319.5, 239.5)));
  EXPECT_EQ(cv::countNonZero(m.D()), 0);
  EXPECT_EQ(m.distortionModel(), "plumb_bob");
  EXPECT_FALSE(m.isFisheye());
  // Without the size: projection yes, reprojection into an image no.
  const CameraModel noSize(525, 525, 320, 240);
  EXPECT_TRUE(noSize.isValidForProjection());
  EXPECT_FALSE(noSize.isValidForReprojection());
  // Right camera of a stereo pair: Tx = -fx * baseline.
  const CameraModel right(500, 500, 320, 240, Transform::Identity(), -500 * 0.12);
  EXPECT_DOUBLE_EQ(right.Tx(), -60.0);
  EXPECT_DOUBLE_EQ(right.P().at<double>(0, 3), -60.0);
  // FOV: 2 atan(w / 2fx).
  EXPECT_NEAR(m.horizontalFOV(), 2 * std::atan(320.0 / 525) * 180 / M_PI, 1e-9);
  EXPECT_NEAR(m.verticalFOV(), 2 * std::atan(240.0 / 526) * 180 / M_PI, 1e-9);
  EXPECT_EQ(noSize.horizontalFOV(), 0.0);
}

TEST(CameraModel, OpticalRotation) {
  const Transform t = CameraModel::opticalRotation();
  // Optical z (forward) is base x, optical x (right) is base -y, optical y (down) is base -z.
  EXPECT_LE((t * Eigen::Vector3d(0, 0, 1) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  EXPECT_LE((t * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(0, -1, 0)).norm(), 1e-12);
  EXPECT_LE((t * Eigen::Vector3d(0, 1, 0) - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
  EXPECT_NEAR(t.rotationMatrix().determinant(), 1.0, 1e-12);
  EXPECT_EQ(CameraModel(1, 1, 0, 0).localTransform(), t);
}

TEST(CameraModel, FullConstructorValidatesShapes) {
  const cv::Mat K = makeK(400, 400, 320, 240);
  const cv::Mat D5 = cv::Mat::zeros(1, 5, CV_64FC1);
  EXPECT_NO_THROW(CameraModel("c", kSize, K, D5, cv::Mat(), cv::Mat()));
  EXPECT_THROW(CameraModel("c", kSize, cv::Mat::eye(2, 2, CV_64FC1), D5, cv::Mat(), cv::Mat()), FormatError);
  EXPECT_THROW(CameraModel("c", kSize, cv::Mat(), D5, cv::Mat(), cv::Mat()), FormatError);
  EXPECT_THROW(CameraModel("c", kSize, K, cv::Mat::zeros(1, 3, CV_64FC1), cv::Mat(), cv::Mat()), FormatError);
  EXPECT_THROW(CameraModel("c", kSize, K, cv::Mat::zeros(2, 4, CV_64FC1), cv::Mat(), cv::Mat()), FormatError);
  EXPECT_THROW(CameraModel("c", kSize, K, D5, cv::Mat::eye(2, 3, CV_64FC1), cv::Mat()), FormatError);
  EXPECT_THROW(CameraModel("c", kSize, K, D5, cv::Mat(), cv::Mat::eye(3, 3, CV_64FC1)), FormatError);
  // Defaults: R = I, P = [K | 0]; float inputs and column D are converted.
  cv::Mat Kf;
  K.convertTo(Kf, CV_32F);
  const CameraModel m("c", kSize, Kf, cv::Mat::zeros(8, 1, CV_32FC1), cv::Mat(), cv::Mat());
  EXPECT_EQ(m.K_raw().type(), CV_64FC1);
  EXPECT_EQ(m.D_raw().rows, 1);
  EXPECT_EQ(m.D_raw().cols, 8);
  EXPECT_EQ(m.distortionModel(), "rational_polynomial");
  EXPECT_TRUE(identical(m.R(), cv::Mat::eye(3, 3, CV_64FC1)));
  EXPECT_TRUE(identical(m.P(), makeP(400, 400, 320, 240)));
  // Deep copies: changing the caller's matrix changes nothing.
  cv::Mat Kc = K.clone();
  const CameraModel m2("c", kSize, Kc, D5, cv::Mat(), cv::Mat());
  Kc.at<double>(0, 0) = 1;
  EXPECT_DOUBLE_EQ(m2.K_raw().at<double>(0, 0), 400);
  // Distortion models.
  EXPECT_EQ(CameraModel("c", kSize, K, cv::Mat::zeros(1, 4, CV_64FC1), cv::Mat(), cv::Mat()).distortionModel(),
            "plumb_bob");
  const CameraModel fish("equidistant", kSize, K, cv::Mat::zeros(1, 4, CV_64FC1), cv::Mat(), cv::Mat());
  EXPECT_TRUE(fish.isFisheye());
  CameraModel m4("c", kSize, K, cv::Mat::zeros(1, 4, CV_64FC1), cv::Mat(), cv::Mat());
  m4.setDistortionModel("fisheye");
  EXPECT_EQ(m4.distortionModel(), "equidistant");
  m4.setDistortionModel("radial-tangential");
  EXPECT_EQ(m4.distortionModel(), "plumb_bob");
  EXPECT_THROW(m4.setDistortionModel("bogus"), FormatError);
  CameraModel m5("c", kSize, K, D5, cv::Mat(), cv::Mat());
  EXPECT_THROW(m5.setDistortionModel("equidistant"), FormatError);  // 5 coefficients
}

TEST(CameraModel, ProjectReprojectRoundTrip) {
  const CameraModel m(525.3, 521.7, 318.9, 242.1, CameraModel::opticalRotation(), 0.0, kSize);
  int n = 0;
  for (double v = 0; v < 480; v += 37.3) {
    for (double u = 0; u < 640; u += 41.7) {
      for (double depth : {0.05, 0.5, 1.0, 3.7, 10.0, 80.0}) {
        double x, y, z;
        ASSERT_TRUE(m.project(u, v, depth, x, y, z));
        EXPECT_DOUBLE_EQ(z, depth);
        double u2, v2;
        ASSERT_TRUE(m.reproject(x, y, z, u2, v2));
        EXPECT_NEAR(u2, u, 1e-9);
        EXPECT_NEAR(v2, v, 1e-9);
        int ui, vi;
        EXPECT_TRUE(m.reproject(x, y, z, ui, vi));
        EXPECT_EQ(ui, static_cast<int>(std::floor(u + 0.5)));
        EXPECT_EQ(vi, static_cast<int>(std::floor(v + 0.5)));
        ++n;
      }
    }
  }
  EXPECT_GT(n, 1000);
  // The principal point projects on the optical axis.
  double x, y, z;
  ASSERT_TRUE(m.project(318.9, 242.1, 2.0, x, y, z));
  EXPECT_NEAR(x, 0, 1e-12);
  EXPECT_NEAR(y, 0, 1e-12);
  // Invalid depths.
  for (double bad : {0.0, -1.0, std::nan(""), double(INFINITY)}) {
    EXPECT_FALSE(m.project(10, 10, bad, x, y, z));
    EXPECT_TRUE(std::isnan(x) && std::isnan(y) && std::isnan(z));
  }
  // Behind the camera and outside the image.
  double u, v;
  EXPECT_FALSE(m.reproject(0.1, 0.1, -1.0, u, v));
  EXPECT_FALSE(m.reproject(0.1, 0.1, 0.0, u, v));
  int ui, vi;
  EXPECT_FALSE(m.reproject(10.0, 0.0, 1.0, ui, vi));
  EXPECT_TRUE(m.inFrame(0, 0));
  EXPECT_TRUE(m.inFrame(639, 479));
  EXPECT_FALSE(m.inFrame(640, 0));
  EXPECT_FALSE(m.inFrame(0, 480));
  EXPECT_FALSE(m.inFrame(-1, 0));
}

TEST(CameraModel, ScaledAndRoi) {
  const CameraModel m(500, 510, 320, 240, CameraModel::opticalRotation(), -50, kSize);
  const CameraModel h = m.scaled(0.5);
  EXPECT_DOUBLE_EQ(h.fx(), 250);
  EXPECT_DOUBLE_EQ(h.fy(), 255);
  EXPECT_DOUBLE_EQ(h.cx(), 160);
  EXPECT_DOUBLE_EQ(h.cy(), 120);
  EXPECT_DOUBLE_EQ(h.Tx(), -25);
  EXPECT_EQ(h.imageSize(), cv::Size(320, 240));
  EXPECT_DOUBLE_EQ(h.K_raw().at<double>(0, 0), 250);
  EXPECT_DOUBLE_EQ(h.K_raw().at<double>(2, 2), 1);
  EXPECT_EQ(h.localTransform(), m.localTransform());
  EXPECT_NEAR(h.horizontalFOV(), m.horizontalFOV(), 1e-9);
  // The same 3D point lands at half the pixel coordinates.
  double u, v, hu, hv;
  m.reproject(0.3, -0.2, 2.0, u, v);
  h.reproject(0.3, -0.2, 2.0, hu, hv);
  EXPECT_NEAR(hu, u * 0.5, 1e-9);
  EXPECT_NEAR(hv, v * 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(m.fx(), 500);  // original untouched
  EXPECT_THROW(m.scaled(0.0), std::invalid_argument);

  const CameraModel r = m.roi(cv::Rect(100, 50, 200, 150));
  EXPECT_DOUBLE_EQ(r.fx(), 500);
  EXPECT_DOUBLE_EQ(r.cx(), 220);
  EXPECT_DOUBLE_EQ(r.cy(), 190);
  EXPECT_EQ(r.imageSize(), cv::Size(200, 150));
  double ru, rv;
  r.reproject(0.3, -0.2, 2.0, ru, rv);
  EXPECT_NEAR(ru, u - 100, 1e-9);
  EXPECT_NEAR(rv, v - 50, 1e-9);
  EXPECT_DOUBLE_EQ(m.cx(), 320);
}

TEST(CameraModel, RectifyPassThroughWithoutDistortion) {
  const CameraModel m(500, 500, 320, 240, CameraModel::opticalRotation(), 0, kSize);
  cv::Mat img(kSize, CV_8UC3, cv::Scalar(1, 2, 3));
  const cv::Mat out = m.rectifyImage(img);
  EXPECT_EQ(out.data, img.data);  // not even copied
  EXPECT_TRUE(m.rectifyImage(cv::Mat()).empty());
}

TEST(CameraModel, RectifyPlumbBobBlobsMapBack) {
  // EuRoC-like strong barrel distortion with 4, 5 and 8 coefficients, with and without R.
  checkBlobsMapBack(distortedModel((cv::Mat_<double>(1, 4) << -0.28, 0.074, 0.0002, 0.00002)));
  checkBlobsMapBack(distortedModel((cv::Mat_<double>(1, 5) << -0.25, 0.08, 0.001, -0.0005, -0.01)));
  checkBlobsMapBack(distortedModel((cv::Mat_<double>(1, 8) << 0.3, 0.05, 0.0005, 0.0003, 0.001, 0.6, 0.1, 0.005)));
  checkBlobsMapBack(distortedModel((cv::Mat_<double>(1, 5) << -0.2, 0.05, 0, 0, 0),
                                   rotationMat(0.01, -0.02, 0.015)));
}

TEST(CameraModel, RectifyEquidistantBlobsMapBack) {
  CameraModel m = distortedModel((cv::Mat_<double>(1, 4) << -0.01, 0.02, -0.005, 0.001), cv::Mat(),
                                 "equidistant");
  ASSERT_TRUE(m.isFisheye());
  checkBlobsMapBack(m);
  // Explicit model on a camera with another name, stronger fisheye distortion.
  CameraModel f = distortedModel((cv::Mat_<double>(1, 4) << 0.1, -0.05, 0.01, -0.002), cv::Mat(), "fish");
  f.setDistortionModel("equidistant");
  checkBlobsMapBack(f);
}

TEST(CameraModel, RectifiedCheckerboardHasStraightEdges) {
  const CameraModel m = distortedModel((cv::Mat_<double>(1, 5) << -0.28, 0.07, 0.0005, -0.0003, 0.0));
  const int square = 40;
  auto checker = [&](double u, double v) {
    return ((static_cast<int>(std::floor(u / square)) + static_cast<int>(std::floor(v / square))) & 1) ? 255 : 0;
  };
  // Raw image: what the distorted camera sees of a checkerboard drawn on the rectified plane.
  cv::Mat raw(kSize, CV_8UC1);
  for (int v = 0; v < raw.rows; ++v) {
    for (int u = 0; u < raw.cols; ++u) {
      const cv::Point2d r = rectifiedPixelOf(m, u, v);
      raw.at<uchar>(v, u) = static_cast<uchar>(checker(r.x, r.y));
    }
  }
  const cv::Mat rect = m.rectifyImage(raw);
  // In the rectified image, the checkerboard's edges are straight, axis-aligned lines: every
  // pixel away from an edge (and whose source is inside the raw image) has the ideal colour.
  int compared = 0, wrong = 0;
  for (int v = 0; v < rect.rows; ++v) {
    for (int u = 0; u < rect.cols; ++u) {
      const double du = std::abs(std::remainder(u, square)), dv = std::abs(std::remainder(v, square));
      if (du < 1.5 || dv < 1.5) continue;
      const cv::Point2d src = rawPixelOf(m, u, v);
      if (src.x < 2 || src.y < 2 || src.x > kSize.width - 3 || src.y > kSize.height - 3) continue;
      ++compared;
      if (std::abs(rect.at<uchar>(v, u) - checker(u, v)) > 64) ++wrong;
    }
  }
  EXPECT_GT(compared, 200000);
  EXPECT_LT(wrong, compared / 1000) << wrong << " of " << compared;
  // And the raw image really was distorted: compared as is, it is badly off near the borders.
  int rawWrong = 0;
  for (int v = 5; v < raw.rows - 5; v += 2) {
    for (int u = 5; u < raw.cols - 5; u += 2) rawWrong += std::abs(raw.at<uchar>(v, u) - checker(u, v)) > 64;
  }
  EXPECT_GT(rawWrong, 5000);
}

TEST(CameraModel, RectifyDepthUsesNearest) {
  const CameraModel m = distortedModel((cv::Mat_<double>(1, 5) << -0.2, 0.05, 0, 0, 0));
  cv::Mat depth(kSize, CV_16UC1);
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) depth.at<uint16_t>(v, u) = (u / 80 % 2) ? 1000 : 3000;
  const cv::Mat out = m.rectifyDepth(depth);
  ASSERT_EQ(out.type(), CV_16UC1);
  int other = 0;
  for (int v = 0; v < out.rows; ++v)
    for (int u = 0; u < out.cols; ++u) {
      const uint16_t d = out.at<uint16_t>(v, u);
      other += (d != 0 && d != 1000 && d != 3000);
    }
  EXPECT_EQ(other, 0) << "nearest neighbour must not blend depths";
  cv::Mat f;
  depth.convertTo(f, CV_32F, 0.001);
  EXPECT_EQ(m.rectifyDepth(f).type(), CV_32FC1);
  EXPECT_THROW(m.rectifyImage(cv::Mat(100, 100, CV_8UC1, cv::Scalar(0))), FormatError);
}

TEST(CameraModel, LazyRectificationIsThreadSafe) {
  const CameraModel m = distortedModel((cv::Mat_<double>(1, 5) << -0.2, 0.05, 0, 0, 0));
  const cv::Mat raw(kSize, CV_8UC1, cv::Scalar(128));
  EXPECT_FALSE(m.isRectificationMapInitialized());
  std::vector<cv::Mat> out(4);
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i) threads.emplace_back([&, i] { out[i] = m.rectifyImage(raw); });
  for (auto& t : threads) t.join();
  EXPECT_TRUE(m.isRectificationMapInitialized());
  for (int i = 1; i < 4; ++i) EXPECT_TRUE(identical(out[0], out[i]));
  // Explicit initialisation gives the same result.
  CameraModel m2 = distortedModel((cv::Mat_<double>(1, 5) << -0.2, 0.05, 0, 0, 0));
  m2.initRectificationMap();
  EXPECT_TRUE(identical(m2.rectifyImage(raw), out[0]));
}

TEST(CameraModel, YamlRoundTrip) {
  rtabmap::test::TempDir dir;
  for (const CameraModel& m :
       {distortedModel((cv::Mat_<double>(1, 5) << -0.28, 0.07, 0.0005, -0.0003, 0.0123456789012345),
                       rotationMat(0.01, -0.02, 0.03), "my camera: left"),
        distortedModel((cv::Mat_<double>(1, 8) << 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8)),
        distortedModel((cv::Mat_<double>(1, 4) << 0.1, 0.2, 0.3, 0.4), cv::Mat(), "equidistant"),
        CameraModel(525.5, 525.25, 319.5, 239.5, Transform(1, 2, 3, 0.1, 0.2, 0.3), -52.55, kSize)}) {
    const std::string path = dir.file("cam.yaml");
    ASSERT_TRUE(m.save(path));
    const CameraModel back = CameraModel::load(path);
    expectSameModel(back, m);
  }
  EXPECT_FALSE(CameraModel(1, 1, 0, 0).save(dir.path() + "/no/such/dir/cam.yaml"));
}

TEST(CameraModel, LoadsRosCameraInfoYaml) {
  // As camera_calibration_parsers writes it (no local_transform: the default optical rotation).
  rtabmap::test::TempDir dir;
  const std::string path = dir.file("ros.yaml");
  std::ofstream(path) << R"(image_width: 752
image_height: 480
camera_name: narrow_stereo/left
camera_matrix:
  rows: 3
  cols: 3
  data: [458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1]
distortion_model: plumb_bob
distortion_coefficients:
  rows: 1
  cols: 5
  data: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0]
rectification_matrix:
  rows: 3
  cols: 3
  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]
projection_matrix:
  rows: 3
  cols: 4
  data: [435.2, 0, 367.4, 0, 0, 435.2, 252.2, 0, 0, 0, 1, 0]
)";
  const CameraModel m = CameraModel::load(path);
  EXPECT_EQ(m.name(), "narrow_stereo/left");
  EXPECT_EQ(m.imageSize(), cv::Size(752, 480));
  EXPECT_DOUBLE_EQ(m.K_raw().at<double>(0, 0), 458.654);
  EXPECT_DOUBLE_EQ(m.fx(), 435.2);
  EXPECT_DOUBLE_EQ(m.cy(), 252.2);
  EXPECT_EQ(m.D_raw().cols, 5);
  EXPECT_DOUBLE_EQ(m.D_raw().at<double>(0, 3), 1.76187114e-05);
  EXPECT_EQ(m.distortionModel(), "plumb_bob");
  EXPECT_EQ(m.localTransform(), CameraModel::opticalRotation());
  EXPECT_TRUE(m.isValidForRectification());

  // local_transform as a string works too.
  std::ofstream(path, std::ios::app) << "local_transform: \"0 0 0 -1.5707963267948966 0 -1.5707963267948966\"\n";
  EXPECT_LE((CameraModel::load(path).localTransform().toMatrix4d() -
             CameraModel::opticalRotation().toMatrix4d()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(CameraModel, LoadRejectsBadFiles) {
  rtabmap::test::TempDir dir;
  EXPECT_THROW(CameraModel::load(dir.file("missing.yaml")), FormatError);
  auto expectBad = [&](const std::string& text, const std::string& mention) {
    const std::string path = dir.file("bad.yaml");
    std::ofstream(path) << text;
    try {
      CameraModel::load(path);
      ADD_FAILURE() << "accepted:\n" << text;
    } catch (const FormatError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << what;
      EXPECT_NE(what.find(mention), std::string::npos) << what;
    }
  };
  expectBad("[1, 2, 3", "YAML");
  expectBad("- a\n- b\n", "map");
  expectBad("image_width: 10\nimage_height: 10\n", "camera_matrix");
  expectBad("image_width: 10\nimage_height: 10\ncamera_matrix: {rows: 3, cols: 3, data: [1, 2]}\n",
            "camera_matrix");
  expectBad("image_width: ten\nimage_height: 10\ncamera_matrix: {rows: 3, cols: 3, data: [1,0,0,0,1,0,0,0,1]}\n",
            "bad value");
  expectBad("image_width: 10\nimage_height: 10\ncamera_matrix: {rows: 2, cols: 2, data: [1,0,0,1]}\n", "K");
  expectBad("image_width: 10\nimage_height: 10\ncamera_matrix: {rows: 3, cols: 3, data: [1,0,0,0,1,0,0,0,1]}\n"
            "distortion_model: equidistant\ndistortion_coefficients: {rows: 1, cols: 5, data: [0,0,0,0,0]}\n",
            "equidistant");
}

TEST(CameraModel, BinaryRoundTrip) {
  for (const CameraModel& m :
       {distortedModel((cv::Mat_<double>(1, 5) << -0.28, 0.07, 0.0005, -0.0003, 0.0123456789012345),
                       rotationMat(0.01, -0.02, 0.03), "left"),
        distortedModel((cv::Mat_<double>(1, 4) << 0.1, 0.2, 0.3, 0.4), cv::Mat(), "equidistant"),
        CameraModel(525.5, 525.25, 319.5, 239.5, Transform(), -52.55, kSize), CameraModel()}) {
    const std::vector<unsigned char> blob = m.serialize();
    ASSERT_GE(blob.size(), 8u);
    EXPECT_EQ(blob[0], 'R');
    const CameraModel back = CameraModel::deserialize(blob.data(), blob.size());
    expectSameModel(back, m);
    EXPECT_EQ(back.localTransform().isNull(), m.localTransform().isNull());
    EXPECT_EQ(back.serialize(), blob);
  }
}

TEST(CameraModel, CorruptOrTruncatedBlobThrows) {
  const CameraModel m = distortedModel((cv::Mat_<double>(1, 5) << -0.28, 0.07, 0.0005, -0.0003, 0.0),
                                       cv::Mat(), "left");
  const std::vector<unsigned char> blob = m.serialize();
  EXPECT_THROW(CameraModel::deserialize(nullptr, 0), FormatError);
  EXPECT_THROW(CameraModel::deserialize(blob.data(), 0), FormatError);
  for (size_t n = 1; n < blob.size(); ++n) {
    EXPECT_THROW(CameraModel::deserialize(blob.data(), n), FormatError) << "length " << n;
  }
  // Every single flipped byte is detected.
  for (size_t i = 0; i < blob.size(); ++i) {
    std::vector<unsigned char> bad = blob;
    bad[i] ^= 0x10;
    EXPECT_THROW(CameraModel::deserialize(bad.data(), bad.size()), FormatError) << "byte " << i;
  }
  // Trailing garbage.
  std::vector<unsigned char> longer = blob;
  longer.push_back(0);
  EXPECT_THROW(CameraModel::deserialize(longer.data(), longer.size()), FormatError);
  // A future version is named as such.
  std::vector<unsigned char> future = blob;
  future[3] = 99;
  try {
    CameraModel::deserialize(future.data(), future.size());
    ADD_FAILURE();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("version"), std::string::npos) << e.what();
  }
  // Random garbage.
  cv::RNG rng(rtabmap::test::drawSeed(5));
  for (int i = 0; i < 500; ++i) {
    std::vector<unsigned char> g(1 + rng.uniform(0, 400));
    for (auto& c : g) c = static_cast<unsigned char>(rng.uniform(0, 256));
    if (i % 2) std::copy(blob.begin(), blob.begin() + std::min<size_t>(4, g.size()), g.begin());
    EXPECT_THROW(CameraModel::deserialize(g.data(), g.size()), FormatError);
  }
}

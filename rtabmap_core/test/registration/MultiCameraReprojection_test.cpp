// The multi-camera PnP residual against OpenCV's projection, its Jacobian against central
// differences through the quaternion manifold, and the Ceres refinement on a two-camera rig.
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include <memory>
#include <random>
#include <vector>

#include "../../src/registration/MultiCameraReprojectionCost.h"
#include "common/TestData.h"

namespace rtabmap {
namespace {

using registration_internal::CameraObservation;
using registration_internal::MultiCameraReprojectionCost;
using registration_internal::PinholeCamera;

Eigen::Isometry3d pose(double x, double y, double z, double roll, double pitch, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

// A rig: a forward camera and one looking left, both optical frames (z forward, x right, y
// down) mounted on a base with x forward, y left, z up.
std::vector<PinholeCamera> rig() {
  const Eigen::Isometry3d forward = pose(0.1, 0.0, 0.5, -M_PI / 2, 0.0, -M_PI / 2);
  const Eigen::Isometry3d left = pose(0.0, 0.1, 0.5, -M_PI / 2, 0.0, 0.0);
  return {{forward.inverse(), 525.0, 525.0, 319.5, 239.5}, {left.inverse(), 500.0, 510.0, 320.0, 240.0}};
}

// Pixel of a reference point seen by camera c after the base moved by `motion`, by OpenCV.
Eigen::Vector2d opencvPixel(const PinholeCamera& c, const Eigen::Isometry3d& motion, const Eigen::Vector3d& X) {
  const Eigen::Isometry3d cameraFromReference = c.opticalFromBase * motion.inverse();
  cv::Mat R, rvec, tvec;
  cv::eigen2cv(Eigen::Matrix3d(cameraFromReference.linear()), R);
  cv::Rodrigues(R, rvec);
  cv::eigen2cv(Eigen::Vector3d(cameraFromReference.translation()), tvec);
  const cv::Matx33d K(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
  std::vector<cv::Point2d> pixels;
  cv::projectPoints(std::vector<cv::Point3d>{{X.x(), X.y(), X.z()}}, rvec, tvec, K, cv::noArray(), pixels);
  return {pixels[0].x, pixels[0].y};
}

// Parameter blocks of the residual for a motion: reference in the new base frame.
void parameters(const Eigen::Isometry3d& motion, double q[4], double t[3]) {
  const Eigen::Isometry3d inverse = motion.inverse();
  Eigen::Map<Eigen::Quaterniond> rotation(q);
  Eigen::Map<Eigen::Vector3d> translation(t);
  rotation = Eigen::Quaterniond(inverse.rotation()).normalized();
  translation = inverse.translation();
}

Eigen::Vector2d residual(const CameraObservation& o, const PinholeCamera& c, const Eigen::Isometry3d& motion) {
  double q[4], t[3];
  parameters(motion, q, t);
  Eigen::Vector2d r;
  MultiCameraReprojectionCost(o, c)(q, t, r.data());
  return r;
}

TEST(MultiCameraReprojection, ResidualIsTheReprojectionErrorOpenCVComputes) {
  const std::vector<PinholeCamera> cams = rig();
  const Eigen::Isometry3d truth = pose(0.3, -0.1, 0.02, 0.01, -0.02, 0.2);
  const Eigen::Isometry3d other = pose(0.32, -0.08, 0.0, 0.0, 0.0, 0.23);
  const std::vector<std::pair<Eigen::Vector3d, int>> points = {{{3.0, 0.5, 0.8}, 0}, {{0.2, 2.5, 0.3}, 1}};
  for (const auto& [X, camera] : points) {
    CameraObservation o;
    o.point = X;
    o.camera = camera;
    o.pixel = opencvPixel(cams[camera], truth, X);
    EXPECT_LT(residual(o, cams[camera], truth).norm(), 1e-9);
    // Under another pose: exactly the pixel difference OpenCV gives.
    const Eigen::Vector2d expected = opencvPixel(cams[camera], other, X) - o.pixel;
    EXPECT_GT(expected.norm(), 5.0);
    EXPECT_LT((residual(o, cams[camera], other) - expected).norm(), 1e-9);
  }
}

TEST(MultiCameraReprojection, JacobianMatchesCentralDifferencesOnTheManifold) {
  const std::vector<PinholeCamera> cams = rig();
  CameraObservation o;
  o.point = Eigen::Vector3d(0.4, 3.0, -0.2);
  o.camera = 1;
  o.pixel = Eigen::Vector2d(300.0, 250.0);
  std::unique_ptr<ceres::CostFunction> cost(MultiCameraReprojectionCost::create(o, cams[1]));
  double q[4], t[3];
  parameters(pose(0.1, 0.2, 0.0, 0.02, 0.01, 0.3), q, t);
  const double* blocks[] = {q, t};
  Eigen::Vector2d r;
  Eigen::Matrix<double, 2, 4, Eigen::RowMajor> jq;
  Eigen::Matrix<double, 2, 3, Eigen::RowMajor> jt;
  double* jacobians[] = {jq.data(), jt.data()};
  ASSERT_TRUE(cost->Evaluate(blocks, r.data(), jacobians));
  // Rotation: the ambient Jacobian times the manifold's PlusJacobian against differences of
  // the residual through Plus.
  const ceres::EigenQuaternionManifold manifold;
  Eigen::Matrix<double, 4, 3, Eigen::RowMajor> plusJacobian;
  manifold.PlusJacobian(q, plusJacobian.data());
  const Eigen::Matrix<double, 2, 3> analyticRotation = jq * plusJacobian;
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    double delta[3] = {0, 0, 0}, qp[4], qm[4];
    delta[k] = h;
    manifold.Plus(q, delta, qp);
    delta[k] = -h;
    manifold.Plus(q, delta, qm);
    Eigen::Vector2d rp, rm;
    const double* bp[] = {qp, t};
    const double* bm[] = {qm, t};
    cost->Evaluate(bp, rp.data(), nullptr);
    cost->Evaluate(bm, rm.data(), nullptr);
    EXPECT_LT((analyticRotation.col(k) - (rp - rm) / (2 * h)).norm(), 1e-4) << "rotation " << k;
  }
  for (int k = 0; k < 3; ++k) {
    double tp[3] = {t[0], t[1], t[2]}, tm[3] = {t[0], t[1], t[2]};
    tp[k] += h;
    tm[k] -= h;
    Eigen::Vector2d rp, rm;
    const double* bp[] = {q, tp};
    const double* bm[] = {q, tm};
    cost->Evaluate(bp, rp.data(), nullptr);
    cost->Evaluate(bm, rm.data(), nullptr);
    EXPECT_LT((jt.col(k) - (rp - rm) / (2 * h)).norm(), 1e-4) << "translation " << k;
  }
}

TEST(MultiCameraReprojection, RefinementRecoversTheMotionFromBothCameras) {
  const std::vector<PinholeCamera> cams = rig();
  const Eigen::Isometry3d truth = pose(0.25, 0.05, 0.0, 0.0, 0.0, 0.15);
  std::mt19937 rng(rtabmap::test::drawSeed(7));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<CameraObservation> obs;
  for (int i = 0; i < 40; ++i) {
    CameraObservation o;
    o.camera = i % 2;
    // In front of each camera, 2-5 m away, in the reference frame.
    const double a = u(rng), b = u(rng), h = u(rng);  // in this order on every compiler
    o.point = o.camera == 0 ? Eigen::Vector3d(3.5 + 1.5 * a, 1.0 * b, 0.5 + 0.8 * h)
                            : Eigen::Vector3d(0.8 * a, 3.5 + 1.5 * b, 0.5 + 0.8 * h);
    o.pixel = opencvPixel(cams[o.camera], truth, o.point);
    obs.push_back(o);
  }
  std::vector<int> inliers(obs.size());
  for (size_t i = 0; i < inliers.size(); ++i) inliers[i] = static_cast<int>(i);
  const Eigen::Isometry3d start = truth * pose(0.03, -0.02, 0.01, 0.01, -0.01, 0.02);
  const Eigen::Isometry3d refined =
      registration_internal::refineMultiCameraReprojection(start, obs, inliers, cams, 20);
  EXPECT_LT((refined.translation() - truth.translation()).norm(), 1e-6);
  EXPECT_LT(Eigen::AngleAxisd(refined.linear().transpose() * truth.linear()).angle(), 1e-6);
}

}  // namespace
}  // namespace rtabmap

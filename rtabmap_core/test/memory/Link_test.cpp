#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "rtabmap_core/memory/Link.h"

namespace rtabmap {
namespace {

Link::InfMatrix diagonal(double x, double y, double z, double roll, double pitch, double yaw) {
  Link::InfMatrix m = Link::InfMatrix::Zero();
  m.diagonal() << x, y, z, roll, pitch, yaw;
  return m;
}

// (x y z roll pitch yaw) of a transform close to identity: the twist of a small motion.
Eigen::Matrix<double, 6, 1> smallTwist(const Transform& t) {
  double x, y, z, roll, pitch, yaw;
  t.getTranslationAndEulerAngles(x, y, z, roll, pitch, yaw);
  Eigen::Matrix<double, 6, 1> v;
  v << x, y, z, roll, pitch, yaw;
  return v;
}

TEST(Link, InverseSwapsIdsAndInvertsTransform) {
  const Transform t(1.0, 2.0, 0.5, 0.1, -0.2, 0.7);
  const Link link(3, 8, Link::kGlobalClosure, t, diagonal(10, 20, 30, 40, 50, 60));
  const Link inv = link.inverse();
  EXPECT_EQ(8, inv.from());
  EXPECT_EQ(3, inv.to());
  EXPECT_EQ(Link::kGlobalClosure, inv.type());
  EXPECT_LT((inv.transform() * t).getNorm(), 1e-12);
  EXPECT_LT((inv.transform() * t).getAngle(), 1e-12);
  // Inverting twice gives the link back (up to rounding).
  const Link back = inv.inverse();
  EXPECT_EQ(3, back.from());
  EXPECT_LT((back.transform().inverse() * t).getNorm(), 1e-12);
  EXPECT_TRUE(back.infMatrix().isApprox(link.infMatrix(), 1e-9));
  EXPECT_TRUE(inv.isValid());
}

TEST(Link, InverseMovesInformationToTheOtherFrame) {
  // A pure rotation of 90 degrees about z: what was well known along x of `from` is along y
  // of `to`... with the inverse rotation: x_from = -y_to, so the x information goes to y.
  const Link link(1, 2, Link::kNeighbor, Transform(0, 0, 0, 0, 0, M_PI / 2), diagonal(100, 1, 1, 1, 1, 1));
  const Link::InfMatrix inv = link.inverse().infMatrix();
  EXPECT_NEAR(1.0, inv(0, 0), 1e-9);
  EXPECT_NEAR(100.0, inv(1, 1), 1e-9);
  // A pure translation with isotropic information keeps it unchanged (the original's
  // assumption for every link).
  const Link translation(1, 2, Link::kNeighbor, Transform(3, 1, 0, 0, 0, 0), Link::InfMatrix::Identity() * 5);
  const Eigen::Matrix3d translational = translation.inverse().infMatrix().topLeftCorner<3, 3>();
  EXPECT_TRUE(translational.isApprox(Eigen::Matrix3d::Identity() * 5));
}

TEST(Link, InverseInformationMatchesTheNoiseOfTheInverse) {
  // First-order check of the adjoint: perturb T on the right by xi, and measure the
  // perturbation xi' of the inverse, T_noisy^-1 = T^-1 * Exp(xi'). Then xi' = -Ad(T) xi, and
  // the information of the inverse must give the same Mahalanobis norm: xi'^T O' xi' ==
  // xi^T O xi.
  const Transform t(2.0, -1.0, 0.3, 0.2, 0.1, -0.5);
  Link::InfMatrix information = diagonal(100, 50, 20, 400, 300, 200);
  information(0, 5) = information(5, 0) = 10;
  const Link link(1, 2, Link::kNeighbor, t, information);
  const Link::InfMatrix invInformation = link.inverse().infMatrix();
  const double eps = 1e-5;
  for (int axis = 0; axis < 6; ++axis) {
    Eigen::Matrix<double, 6, 1> xi = Eigen::Matrix<double, 6, 1>::Zero();
    xi(axis) = eps;
    xi((axis + 2) % 6) = -0.5 * eps;
    const Transform noisy = t * Transform(xi(0), xi(1), xi(2), xi(3), xi(4), xi(5));
    const Eigen::Matrix<double, 6, 1> xiInv = smallTwist(t * noisy.inverse());
    const double before = xi.dot(information * xi);
    const double after = xiInv.dot(invInformation * xiInv);
    EXPECT_NEAR(1.0, after / before, 1e-3) << "axis " << axis;
  }
}

TEST(Link, ComposeChainsIdsAndTransforms) {
  const Transform a(1.0, 0.5, 0.0, 0.0, 0.0, M_PI / 2), b(2.0, 0.0, 0.1, 0.1, 0.0, 0.3);
  const Link ab(4, 7, Link::kGlobalClosure, a, diagonal(10, 10, 10, 100, 100, 100));
  const Link bc(7, 9, Link::kNeighbor, b, diagonal(20, 20, 20, 200, 200, 200));
  const Link ac = ab.compose(bc, Link::kNeighborMerged);
  EXPECT_EQ(4, ac.from());
  EXPECT_EQ(9, ac.to());
  EXPECT_EQ(Link::kNeighborMerged, ac.type());
  EXPECT_LT(((a * b).inverse() * ac.transform()).getNorm(), 1e-12);
  EXPECT_TRUE(ac.isValid());
  // In series the noise only grows: less information on every axis than either link.
  for (int i = 0; i < 6; ++i) EXPECT_LT(ac.infMatrix()(i, i), bc.infMatrix()(i, i)) << i;
  EXPECT_THROW(bc.compose(ab, Link::kNeighborMerged), std::invalid_argument);
  EXPECT_THROW(ab.compose(Link(7, 9, Link::kNeighbor, Transform()), Link::kNeighborMerged), std::invalid_argument);
}

TEST(Link, ComposedInformationMatchesTheNoiseOfTheChain) {
  // Monte Carlo: draw each link's noise from its covariance (right perturbation, as the
  // optimiser), compose the noisy transforms and measure the composed noise in the frame of
  // the result. Its Mahalanobis norm under the composed information is chi-square with 6
  // degrees of freedom: mean 6. The first link is unsure of its heading and the second is 2 m
  // long, so the heading swings the end sideways: summing the covariances without moving the
  // first one through the second (the original's merge) misses that.
  const Transform a(1.0, 0.2, 0.0, 0.0, 0.0, 0.4), b(2.0, 0.3, 0.0, 0.0, 0.0, -0.2);
  Link::InfMatrix infA = diagonal(1e6, 1e6, 1e6, 4e4, 4e4, 1e4);
  infA(0, 5) = infA(5, 0) = 1e4;
  const Link ab(1, 2, Link::kNeighbor, a, infA);
  const Link bc(2, 3, Link::kNeighbor, b, diagonal(4e5, 1e5, 1e6, 1e5, 1e5, 1e5));
  const Link ac = ab.compose(bc, Link::kNeighborMerged);
  const Eigen::Matrix<double, 6, 6> naive = (ab.infMatrix().inverse() + bc.infMatrix().inverse()).inverse();

  std::mt19937 rng(11);
  std::normal_distribution<double> unit(0.0, 1.0);
  const auto draw = [&](const Link::InfMatrix& information) {
    const Eigen::Matrix<double, 6, 6> l = Eigen::LLT<Eigen::Matrix<double, 6, 6>>(information.inverse()).matrixL();
    Eigen::Matrix<double, 6, 1> z;
    for (int i = 0; i < 6; ++i) z(i) = unit(rng);
    const Eigen::Matrix<double, 6, 1> xi = l * z;
    return Transform(xi(0), xi(1), xi(2), xi(3), xi(4), xi(5));
  };
  const int n = 20000;
  double composed = 0.0, summed = 0.0;
  for (int k = 0; k < n; ++k) {
    const Transform noisy = a * draw(ab.infMatrix()) * b * draw(bc.infMatrix());
    const Eigen::Matrix<double, 6, 1> xi = smallTwist(ac.transform().inverse() * noisy);
    composed += xi.dot(ac.infMatrix() * xi);
    summed += xi.dot(naive * xi);
  }
  composed /= n;
  summed /= n;
  EXPECT_NEAR(6.0, composed, 0.15);  // the mean's standard error is sqrt(12 / n) = 0.025
  EXPECT_GT(std::fabs(summed - 6.0), 1.0) << "the test does not tell the adjoint from a plain sum";
}

TEST(Link, ScanIdsUserDataIsTheOriginalsText) {
  Link link(3, 1, Link::kLocalSpaceClosure, Transform::Identity(), Link::InfMatrix::Identity(),
            Link::scanIdsUserData({1, 2, 5}));
  const cv::Mat& d = link.userData();
  EXPECT_EQ(std::string(d.ptr<char>(0), d.ptr<char>(0) + d.cols), "SCANS:1;2;5");
  EXPECT_TRUE(link.hasScanIdsUserData());
  EXPECT_TRUE(link.inverse().hasScanIdsUserData());
  link.setUserData(cv::Mat(1, 4, CV_8UC1, cv::Scalar(7)));  // a user's bytes
  EXPECT_FALSE(link.hasScanIdsUserData());
  link.setUserData(cv::Mat());
  EXPECT_FALSE(link.hasScanIdsUserData());
}

TEST(Link, ValidityExplainsWhy) {
  std::string why;
  EXPECT_TRUE(Link(1, 2, Link::kNeighbor, Transform::Identity()).isValid(&why)) << why;
  EXPECT_TRUE(why.empty());

  EXPECT_FALSE(Link(1, 2, Link::kUndef, Transform::Identity()).isValid(&why));
  EXPECT_NE(std::string::npos, why.find("undefined type")) << why;

  EXPECT_FALSE(Link(1, 2, Link::kNeighbor, Transform()).isValid(&why));
  EXPECT_NE(std::string::npos, why.find("null transform")) << why;

  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(Link(1, 2, Link::kNeighbor, Transform(nan, 0, 0, 0, 0, 0)).isValid(&why));
  EXPECT_NE(std::string::npos, why.find("non-finite transform")) << why;

  Link::InfMatrix info = Link::InfMatrix::Identity();
  info(2, 2) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(Link(1, 2, Link::kNeighbor, Transform::Identity(), info).isValid(&why));
  EXPECT_NE(std::string::npos, why.find("non-finite information")) << why;

  info = Link::InfMatrix::Identity();
  info(0, 1) = 0.5;
  EXPECT_FALSE(Link(1, 2, Link::kNeighbor, Transform::Identity(), info).isValid(&why));
  EXPECT_NE(std::string::npos, why.find("non-symmetric")) << why;

  info = Link::InfMatrix::Identity();
  info(4, 4) = 0.0;
  EXPECT_FALSE(Link(1, 2, Link::kNeighbor, Transform::Identity(), info).isValid(&why));
  EXPECT_NE(std::string::npos, why.find("not positive definite")) << why;
  info(4, 4) = -1.0;
  EXPECT_FALSE(Link(1, 2, Link::kNeighbor, Transform::Identity(), info).isValid(nullptr));
}

TEST(Link, VariancesFromInformation) {
  const Link link(1, 2, Link::kNeighbor, Transform::Identity(), diagonal(100, 50, 25, 1000, 500, 250));
  EXPECT_DOUBLE_EQ(0.01, link.transVariance());
  EXPECT_DOUBLE_EQ(0.04, link.transVariance(false));
  EXPECT_DOUBLE_EQ(0.001, link.rotVariance());
  EXPECT_DOUBLE_EQ(0.004, link.rotVariance(false));
}

TEST(Link, TypeNamesFollowTheMessageNumbers) {
  EXPECT_EQ("Neighbor", Link::typeName(0));
  EXPECT_EQ("GlobalClosure", Link::typeName(1));
  EXPECT_EQ("LocalSpaceClosure", Link::typeName(2));
  EXPECT_EQ("LocalTimeClosure", Link::typeName(3));
  EXPECT_EQ("UserClosure", Link::typeName(4));
  EXPECT_EQ("VirtualClosure", Link::typeName(5));
  EXPECT_EQ("NeighborMerged", Link::typeName(6));
  EXPECT_EQ("PosePrior", Link::typeName(7));
  EXPECT_EQ("Landmark", Link::typeName(8));
  EXPECT_EQ("Gravity", Link::typeName(9));
  EXPECT_EQ("Temporary", Link::typeName(10));
  EXPECT_EQ("Undefined", Link::typeName(-1));
  EXPECT_EQ("Undefined", Link::typeName(11));
  EXPECT_EQ(Link::kUndef, Link::typeFromInt(42));
  EXPECT_EQ(Link::kGravity, Link::typeFromInt(9));
  EXPECT_EQ("Landmark", Link(1, -3, Link::kLandmark, Transform::Identity()).typeName());
}

}  // namespace
}  // namespace rtabmap

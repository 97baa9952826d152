#include <gtest/gtest.h>

#include <cmath>
#include <limits>

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

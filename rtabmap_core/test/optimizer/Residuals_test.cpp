// Every residual of the optimiser against numerical derivatives (central differences through
// the same parameter increment the solver applies), and the auto-diff versions against the
// analytic ones.
#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <vector>

#include "../../src/optimizer/GravityResidual.h"
#include "../../src/optimizer/PriorResidual.h"
#include "../../src/optimizer/Se2Residual.h"
#include "../../src/optimizer/Se3Manifold.h"
#include "../../src/optimizer/Se3Residual.h"
#include "common/TestData.h"
#include "rtabmap_core/optimizer/Chi2.h"

namespace rtabmap {
namespace {

using namespace optimizer_internal;
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Applies a tangent increment to one parameter block.
using PlusFn = std::function<void(const double* x, const double* delta, double* out)>;

void euclideanPlus(int n, const double* x, const double* d, double* out) {
  for (int i = 0; i < n; ++i) out[i] = x[i] + d[i];
}

const PlusFn kPlus3 = [](const double* x, const double* d, double* out) { euclideanPlus(3, x, d, out); };
const PlusFn kPlusSe3 = [](const double* x, const double* d, double* out) {
  Se3TangentManifold().Plus(x, d, out);
};

// Checks the analytic Jacobian of each block (first tangentSize columns) against central
// differences of the residual through `plus`, and that extra ambient columns are zero.
void expectJacobiansMatchNumerical(const ceres::CostFunction& cost,
                                   std::vector<std::vector<double>> blocks,
                                   const std::vector<int>& tangentSizes,
                                   const std::vector<PlusFn>& plus, double tolerance = 1e-6) {
  const int m = cost.num_residuals();
  const auto& sizes = cost.parameter_block_sizes();
  std::vector<const double*> params;
  for (auto& b : blocks) params.push_back(b.data());
  std::vector<RowMajor> jac;
  std::vector<double*> jacPtr;
  for (int size : sizes) jac.emplace_back(RowMajor::Zero(m, size));
  for (auto& j : jac) jacPtr.push_back(j.data());
  Eigen::VectorXd r0(m);
  ASSERT_TRUE(cost.Evaluate(params.data(), r0.data(), jacPtr.data()));

  const double h = 1e-6;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    for (int k = 0; k < tangentSizes[b]; ++k) {
      std::vector<double> delta(tangentSizes[b], 0.0);
      std::vector<double> xp(sizes[b]), xm(sizes[b]);
      delta[k] = h;
      plus[b](blocks[b].data(), delta.data(), xp.data());
      delta[k] = -h;
      plus[b](blocks[b].data(), delta.data(), xm.data());
      std::vector<const double*> pp = params, pm = params;
      pp[b] = xp.data();
      pm[b] = xm.data();
      Eigen::VectorXd rp(m), rm(m);
      cost.Evaluate(pp.data(), rp.data(), nullptr);
      cost.Evaluate(pm.data(), rm.data(), nullptr);
      const Eigen::VectorXd numeric = (rp - rm) / (2 * h);
      for (int i = 0; i < m; ++i) {
        EXPECT_NEAR(jac[b](i, k), numeric[i], tolerance * std::max(1.0, std::fabs(numeric[i])))
            << "block " << b << " residual " << i << " tangent " << k;
      }
    }
    for (int k = tangentSizes[b]; k < sizes[b]; ++k) {
      for (int i = 0; i < m; ++i) EXPECT_EQ(jac[b](i, k), 0.0) << "ambient column " << k;
    }
  }
}

// Compares residuals and the ambient Jacobians of two cost functions (analytic and auto-diff),
// the latter through numerical differences in ambient coordinates.
void expectSameResiduals(const ceres::CostFunction& a, const ceres::CostFunction& b,
                         std::vector<std::vector<double>> blocks) {
  std::vector<const double*> params;
  for (auto& block : blocks) params.push_back(block.data());
  Eigen::VectorXd ra(a.num_residuals()), rb(b.num_residuals());
  ASSERT_TRUE(a.Evaluate(params.data(), ra.data(), nullptr));
  ASSERT_TRUE(b.Evaluate(params.data(), rb.data(), nullptr));
  EXPECT_LT((ra - rb).cwiseAbs().maxCoeff(), 1e-12);
}

// Auto-diff Jacobians (ambient) against central differences in ambient coordinates.
void expectAutoDiffMatchesNumerical(const ceres::CostFunction& cost,
                                    std::vector<std::vector<double>> blocks) {
  std::vector<PlusFn> plus;
  std::vector<int> tangent;
  for (int size : cost.parameter_block_sizes()) {
    plus.push_back([size](const double* x, const double* d, double* out) { euclideanPlus(size, x, d, out); });
    tangent.push_back(size);
  }
  expectJacobiansMatchNumerical(cost, blocks, tangent, plus, 1e-5);
}

Eigen::Matrix3d randomSqrtInfo3(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3d a;
  for (int i = 0; i < 9; ++i) a.data()[i] = u(rng);
  const Eigen::Matrix3d omega = a * a.transpose() + 0.5 * Eigen::Matrix3d::Identity();
  Eigen::Matrix3d s;
  EXPECT_TRUE(sqrtInformation<3>(omega, &s));
  return s;
}

Matrix6 randomSqrtInfo6(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Matrix6 a;
  for (int i = 0; i < 36; ++i) a.data()[i] = u(rng);
  const Matrix6 omega = a * a.transpose() + 0.5 * Matrix6::Identity();
  Matrix6 s;
  EXPECT_TRUE(sqrtInformation<6>(omega, &s));
  return s;
}

Transform randomPose(std::mt19937& rng, double angleScale = M_PI) {
  std::uniform_real_distribution<double> t(-5.0, 5.0), a(-angleScale, angleScale);
  return Transform{t(rng), t(rng), t(rng), a(rng), a(rng) / 2, a(rng)};  // braces: drawn in order
}

std::vector<double> se3Block(const Transform& t) {
  std::vector<double> b(7);
  toSE3Block(t, b.data());
  return b;
}

TEST(Residuals, SqrtInformationIsTheUpperCholeskyFactor) {
  Eigen::Matrix3d omega;
  omega << 4, 1, 0, 1, 3, 0.5, 0, 0.5, 2;
  Eigen::Matrix3d u;
  ASSERT_TRUE(sqrtInformation<3>(omega, &u));
  EXPECT_LT((u.transpose() * u - omega).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(u(1, 0), 0.0);
  Eigen::Matrix3d notPd = omega;
  notPd(2, 2) = -1;
  EXPECT_FALSE(sqrtInformation<3>(notPd, &u));
}

TEST(Residuals, WrapAngleIsInMinusPiPi) {
  EXPECT_DOUBLE_EQ(wrapAngle(M_PI), M_PI);
  EXPECT_NEAR(wrapAngle(-M_PI), M_PI, 1e-15);
  EXPECT_NEAR(wrapAngle(3 * M_PI / 2), -M_PI / 2, 1e-15);
  EXPECT_NEAR(wrapAngle(-7.0), -7.0 + 2 * M_PI, 1e-15);
  EXPECT_NEAR(wrapAngle(0.3), 0.3, 1e-15);
}

TEST(Residuals, Se2EdgeJacobiansMatchNumericalDerivatives) {
  std::mt19937 rng(test::drawSeed(1));
  std::uniform_real_distribution<double> t(-5, 5), a(-M_PI, M_PI);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3d z{t(rng), t(rng), a(rng)};
    Se2EdgeCost cost(z, randomSqrtInfo3(rng));
    std::vector<std::vector<double>> blocks = {{t(rng), t(rng), 3 * a(rng)},
                                               {t(rng), t(rng), 3 * a(rng)}};
    expectJacobiansMatchNumerical(cost, blocks, {3, 3}, {kPlus3, kPlus3});
  }
}

TEST(Residuals, Se2EdgeAutoDiffMatchesAnalytic) {
  std::mt19937 rng(test::drawSeed(2));
  std::uniform_real_distribution<double> t(-5, 5), a(-M_PI, M_PI);
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Vector3d z{t(rng), t(rng), a(rng)};
    const Eigen::Matrix3d s = randomSqrtInfo3(rng);
    std::unique_ptr<ceres::CostFunction> analytic(makeSe2EdgeCost(z, s, false));
    std::unique_ptr<ceres::CostFunction> automatic(makeSe2EdgeCost(z, s, true));
    std::vector<std::vector<double>> blocks = {{t(rng), t(rng), a(rng)}, {t(rng), t(rng), a(rng)}};
    expectSameResiduals(*analytic, *automatic, blocks);
    expectAutoDiffMatchesNumerical(*automatic, blocks);
  }
}

TEST(Residuals, Se2EdgeResidualIsTheG2oChi2) {
  const Transform xi(1, 2, 0.5), xj(2, 4, 3.0), z(1.5, 1.0, 2.4);
  Link link(1, 2, Link::kGlobalClosure, z,
            graph::linkInformationFromSE2((Eigen::Matrix3d() << 5, 1, 0, 1, 4, 0.2, 0, 0.2, 9).finished()));
  Eigen::Matrix3d s;
  ASSERT_TRUE(sqrtInformation<3>(graph::informationSE2(link.infMatrix()), &s));
  Se2EdgeCost cost(toSE2(z), s);
  const Eigen::Vector3d a = toSE2(xi), b = toSE2(xj);
  const double* params[] = {a.data(), b.data()};
  Eigen::Vector3d r;
  cost.Evaluate(params, r.data(), nullptr);
  EXPECT_NEAR(r.squaredNorm(), graph::linkChi2(link, xi, xj, true), 1e-12);
}

TEST(Residuals, Se3EdgeJacobiansMatchNumericalDerivatives) {
  std::mt19937 rng(test::drawSeed(3));
  for (int trial = 0; trial < 20; ++trial) {
    const Transform z = randomPose(rng);
    Se3EdgeCost cost(z.translation(), z.quaternion(), randomSqrtInfo6(rng));
    // Small errors (the usual case near the optimum) and arbitrary ones.
    const Transform xi = randomPose(rng);
    const Transform xj = trial % 2 ? xi * z * Transform(0.1, -0.2, 0.05, 0.1, 0.2, -0.1)
                                   : randomPose(rng);
    expectJacobiansMatchNumerical(cost, {se3Block(xi), se3Block(xj)}, {6, 6}, {kPlusSe3, kPlusSe3});
  }
}

TEST(Residuals, Se3EdgeJacobianHoldsWhenTheErrorQuaternionIsFlipped) {
  // An error rotation of 179 degrees: the raw error quaternion may come out with w < 0 and is
  // flipped; the Jacobian must follow the flipped one.
  const Transform z(0.5, 0, 0, 0, 0, 0);
  const Transform xi = Transform::Identity();
  for (double angle : {3.12, -3.12, 2.0}) {
    const Transform xj = z * Transform(0.1, 0.2, 0.3, 0.0, 0.0, angle);
    std::mt19937 rng(test::drawSeed(4));
    Se3EdgeCost cost(z.translation(), z.quaternion(), randomSqrtInfo6(rng));
    expectJacobiansMatchNumerical(cost, {se3Block(xi), se3Block(xj)}, {6, 6}, {kPlusSe3, kPlusSe3});
    // And the residual really uses w >= 0: qvec ~ sin(angle / 2) about z.
    Se3EdgeCost identityCost(z.translation(), z.quaternion(), Matrix6::Identity());
    const auto a = se3Block(xi), b = se3Block(xj);
    const double* params[] = {a.data(), b.data()};
    Eigen::Matrix<double, 6, 1> r;
    identityCost.Evaluate(params, r.data(), nullptr);
    EXPECT_NEAR(r[5], std::sin(angle / 2), 1e-9);
  }
}

TEST(Residuals, Se3EdgeAutoDiffMatchesAnalytic) {
  std::mt19937 rng(test::drawSeed(5));
  for (int trial = 0; trial < 10; ++trial) {
    const Transform z = randomPose(rng);
    const Matrix6 s = randomSqrtInfo6(rng);
    std::unique_ptr<ceres::CostFunction> analytic(makeSe3EdgeCost(z.translation(), z.quaternion(), s, false));
    std::unique_ptr<ceres::CostFunction> automatic(makeSe3EdgeCost(z.translation(), z.quaternion(), s, true));
    const std::vector<std::vector<double>> blocks = {se3Block(randomPose(rng)), se3Block(randomPose(rng))};
    expectSameResiduals(*analytic, *automatic, blocks);
    expectAutoDiffMatchesNumerical(*automatic, blocks);
  }
}

TEST(Residuals, Se3EdgeResidualIsTheG2oChi2) {
  std::mt19937 rng(test::drawSeed(6));
  const Transform xi = randomPose(rng), xj = randomPose(rng), z = randomPose(rng);
  Link::InfMatrix info = Link::InfMatrix::Identity();
  info.diagonal() << 10, 20, 30, 40, 50, 60;
  info(0, 4) = info(4, 0) = 3;
  const Link link(1, 2, Link::kNeighbor, z, info);
  Matrix6 s;
  ASSERT_TRUE(sqrtInformation<6>(graph::informationSE3ToG2o(info), &s));
  Se3EdgeCost cost(z.translation(), z.quaternion(), s);
  const auto a = se3Block(xi), b = se3Block(xj);
  const double* params[] = {a.data(), b.data()};
  Eigen::Matrix<double, 6, 1> r;
  cost.Evaluate(params, r.data(), nullptr);
  EXPECT_NEAR(r.squaredNorm(), graph::linkChi2(link, xi, xj, false), 1e-9 * r.squaredNorm());
}

TEST(Residuals, PriorJacobiansMatchNumericalDerivatives) {
  std::mt19937 rng(test::drawSeed(7));
  std::uniform_real_distribution<double> t(-5, 5), a(-M_PI, M_PI);
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Vector3d prior{t(rng), t(rng), a(rng)};
    Se2PriorCost se2(prior, randomSqrtInfo3(rng));
    expectJacobiansMatchNumerical(se2, {{t(rng), t(rng), 3 * a(rng)}}, {3}, {kPlus3});
    const Transform z = randomPose(rng);
    Se3PriorCost se3(z.translation(), z.quaternion(), randomSqrtInfo6(rng));
    expectJacobiansMatchNumerical(se3, {se3Block(randomPose(rng))}, {6}, {kPlusSe3});
  }
}

TEST(Residuals, PriorAutoDiffMatchesAnalyticAndTheChi2) {
  std::mt19937 rng(test::drawSeed(8));
  const Transform z = randomPose(rng), x = randomPose(rng);
  const Matrix6 s = randomSqrtInfo6(rng);
  std::unique_ptr<ceres::CostFunction> a3(makeSe3PriorCost(z.translation(), z.quaternion(), s, false));
  std::unique_ptr<ceres::CostFunction> b3(makeSe3PriorCost(z.translation(), z.quaternion(), s, true));
  expectSameResiduals(*a3, *b3, {se3Block(x)});
  expectAutoDiffMatchesNumerical(*b3, {se3Block(x)});
  const Eigen::Matrix3d s2 = randomSqrtInfo3(rng);
  std::unique_ptr<ceres::CostFunction> a2(makeSe2PriorCost(toSE2(z), s2, false));
  std::unique_ptr<ceres::CostFunction> b2(makeSe2PriorCost(toSE2(z), s2, true));
  expectSameResiduals(*a2, *b2, {{x.x(), x.y(), x.yaw()}});

  // A prior's residual is the g2o error of Z^-1 * X.
  const Link prior(3, 3, Link::kPosePrior, z, Link::InfMatrix::Identity());
  Se3PriorCost cost(z.translation(), z.quaternion(), Matrix6::Identity() * 2.0);  // Omega_g2o = 4 on all
  const auto block = se3Block(x);
  const double* params[] = {block.data()};
  Eigen::Matrix<double, 6, 1> r;
  cost.Evaluate(params, r.data(), nullptr);
  // linkChi2 weighs the translation by 1 and the quaternion vector by 4; the cost above by 4 and 4.
  const graph::Vector6 e = graph::errorSE3(Transform::Identity(), x, z);
  EXPECT_NEAR(r.squaredNorm(), 4 * e.squaredNorm(), 1e-9);
  EXPECT_NEAR(graph::linkChi2(prior, x, x, false),
              e.head<3>().squaredNorm() + 4 * e.tail<3>().squaredNorm(), 1e-9);
}

TEST(Residuals, GravityJacobianMatchesNumericalDerivatives) {
  std::mt19937 rng(test::drawSeed(9));
  for (int trial = 0; trial < 10; ++trial) {
    GravityCost cost(randomPose(rng, 0.5).quaternion(), 0.2);
    expectJacobiansMatchNumerical(cost, {se3Block(randomPose(rng))}, {6}, {kPlusSe3});
  }
  const Eigen::Quaterniond measured = randomPose(rng).quaternion();
  std::unique_ptr<ceres::CostFunction> a(makeGravityCost(measured, 0.3, false));
  std::unique_ptr<ceres::CostFunction> b(makeGravityCost(measured, 0.3, true));
  const std::vector<std::vector<double>> blocks = {se3Block(randomPose(rng))};
  expectSameResiduals(*a, *b, blocks);
  expectAutoDiffMatchesNumerical(*b, blocks);
}

TEST(Residuals, GravityIgnoresYawAndSeesRollAndPitch) {
  GravityCost cost(Transform(0, 0, 0, 0.1, -0.2, 0.0).quaternion(), 1.0);
  const auto sameTilt = se3Block(Transform(5, 6, 7, 0.1, -0.2, 2.5));
  const auto otherTilt = se3Block(Transform(5, 6, 7, 0.3, -0.2, 0.0));
  Eigen::Vector3d r;
  const double* p1[] = {sameTilt.data()};
  cost.Evaluate(p1, r.data(), nullptr);
  EXPECT_LT(r.norm(), 1e-12);
  const double* p2[] = {otherTilt.data()};
  cost.Evaluate(p2, r.data(), nullptr);
  EXPECT_GT(r.norm(), 0.1);
}

TEST(Residuals, Se3ManifoldPlusAndMinusAreInverse) {
  std::mt19937 rng(test::drawSeed(10));
  std::uniform_real_distribution<double> d(-0.5, 0.5);
  Se3TangentManifold manifold;
  EXPECT_EQ(manifold.AmbientSize(), 7);
  EXPECT_EQ(manifold.TangentSize(), 6);
  for (int trial = 0; trial < 10; ++trial) {
    const auto x = se3Block(randomPose(rng));
    double delta[6], y[7], back[6];
    for (double& v : delta) v = d(rng);
    ASSERT_TRUE(manifold.Plus(x.data(), delta, y));
    EXPECT_NEAR(Eigen::Map<const Eigen::Quaterniond>(y + 3).norm(), 1.0, 1e-12);
    ASSERT_TRUE(manifold.Minus(y, x.data(), back));
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(back[i], delta[i], 1e-9);
    // The rotation increment is in the body frame: R(y) = R(x) * Exp(delta_r).
    const Transform tx = fromSE3Block(x.data()), ty = fromSE3Block(y);
    const Eigen::Vector3d w(delta[3], delta[4], delta[5]);
    const Eigen::Matrix3d expected = tx.rotationMatrix() * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    EXPECT_LT((ty.rotationMatrix() - expected).cwiseAbs().maxCoeff(), 1e-12);
  }
  // Right-multiplying by the Plus Jacobian keeps the first six columns.
  double ambient[2 * 7], tangent[2 * 6];
  for (int i = 0; i < 14; ++i) ambient[i] = i;
  const auto x = se3Block(Transform::Identity());
  ASSERT_TRUE(manifold.RightMultiplyByPlusJacobian(x.data(), 2, ambient, tangent));
  EXPECT_EQ(tangent[0], 0);
  EXPECT_EQ(tangent[5], 5);
  EXPECT_EQ(tangent[6], 7);
  EXPECT_EQ(tangent[11], 12);
}

}  // namespace
}  // namespace rtabmap

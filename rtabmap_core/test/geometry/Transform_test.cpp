#include "rtabmap_core/geometry/Transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include "common/TestData.h"
#include "rtabmap_core/common/Error.h"

using rtabmap::FormatError;
using rtabmap::Transform;

namespace {

Eigen::Matrix3d eulerRef(double roll, double pitch, double yaw) {
  // Written out element by element (not through the same Eigen calls as the implementation).
  const double cr = std::cos(roll), sr = std::sin(roll);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  Eigen::Matrix3d Rx, Ry, Rz;
  Rx << 1, 0, 0, 0, cr, -sr, 0, sr, cr;
  Ry << cp, 0, sp, 0, 1, 0, -sp, 0, cp;
  Rz << cy, -sy, 0, sy, cy, 0, 0, 0, 1;
  return Rz * Ry * Rx;
}

Transform randomTransform(std::mt19937& rng) {
  std::uniform_real_distribution<double> t(-10, 10), a(-M_PI, M_PI), p(-1.5, 1.5);
  return Transform{t(rng), t(rng), t(rng), a(rng), p(rng), a(rng)};  // braces: drawn in order
}

void expectNear(const Transform& a, const Transform& b, double eps = 1e-9) {
  ASSERT_FALSE(a.isNull());
  ASSERT_FALSE(b.isNull());
  EXPECT_LE((a.toMatrix4d() - b.toMatrix4d()).cwiseAbs().maxCoeff(), eps)
      << a.prettyPrint() << " vs " << b.prettyPrint();
}

}  // namespace

TEST(Transform, DefaultIsNullAndDistinctFromIdentity) {
  Transform t;
  EXPECT_TRUE(t.isNull());
  EXPECT_FALSE(t.isIdentity());
  EXPECT_FALSE(t.isInvalid());
  EXPECT_FALSE(Transform::Identity().isNull());
  EXPECT_TRUE(Transform::Identity().isIdentity());
  EXPECT_NE(t, Transform::Identity());
  EXPECT_EQ(t, Transform());
  EXPECT_EQ(t.toString(), "null");
  EXPECT_EQ(t.prettyPrint(), "null");
}

TEST(Transform, NullMisuseThrowsLogicError) {
  Transform n;
  const Transform i = Transform::Identity();
  EXPECT_THROW(n.x(), std::logic_error);
  EXPECT_THROW(n.yaw(), std::logic_error);
  EXPECT_THROW(n.inverse(), std::logic_error);
  EXPECT_THROW(n * i, std::logic_error);
  EXPECT_THROW(i * n, std::logic_error);
  EXPECT_THROW(n * Eigen::Vector3d(1, 2, 3), std::logic_error);
  EXPECT_THROW(n.toEigen(), std::logic_error);
  EXPECT_THROW(n.toMatrix4d(), std::logic_error);
  EXPECT_THROW(n.getNorm(), std::logic_error);
  EXPECT_THROW(n.getAngle(), std::logic_error);
  EXPECT_THROW(n.interpolate(0.5, i), std::logic_error);
  EXPECT_THROW(i.interpolate(0.5, n), std::logic_error);
  EXPECT_THROW(n.normalized(), std::logic_error);
  EXPECT_THROW(n.to3DoF(), std::logic_error);
  EXPECT_THROW(i.getDistance(n), std::logic_error);
  double a[12];
  EXPECT_THROW(n.toArray12(a), std::logic_error);
  try {
    n.inverse();
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("null"), std::string::npos) << e.what();
  }
}

TEST(Transform, EulerConventionMatchesRzRyRx) {
  std::mt19937 rng(rtabmap::test::drawSeed(1));
  std::uniform_real_distribution<double> a(-M_PI, M_PI), p(-1.55, 1.55);
  for (int i = 0; i < 200; ++i) {
    const double roll = a(rng), pitch = p(rng), yaw = a(rng);
    const Transform t(1, 2, 3, roll, pitch, yaw);
    EXPECT_LE((t.rotationMatrix() - eulerRef(roll, pitch, yaw)).cwiseAbs().maxCoeff(), 1e-12);
    double r2, p2, y2;
    t.getEulerAngles(r2, p2, y2);
    EXPECT_NEAR(r2, roll, 1e-9);
    EXPECT_NEAR(p2, pitch, 1e-9);
    EXPECT_NEAR(y2, yaw, 1e-9);
    EXPECT_DOUBLE_EQ(t.roll(), r2);
    EXPECT_DOUBLE_EQ(t.pitch(), p2);
    EXPECT_DOUBLE_EQ(t.yaw(), y2);
    EXPECT_DOUBLE_EQ(t.theta(), y2);
  }
  // Eigen's own intrinsic z-y'-x'' decomposition agrees.
  const Transform t(0, 0, 0, 0.3, -0.2, 1.1);
  const Eigen::Vector3d ypr = t.rotationMatrix().eulerAngles(2, 1, 0);
  EXPECT_NEAR(ypr[0], 1.1, 1e-12);
  EXPECT_NEAR(ypr[1], -0.2, 1e-12);
  EXPECT_NEAR(ypr[2], 0.3, 1e-12);
}

TEST(Transform, GimbalLockRecomposes) {
  for (double pitch : {M_PI / 2, -M_PI / 2}) {
    const Transform t(0, 0, 0, 0.4, pitch, -0.7);
    double r, p, y;
    t.getEulerAngles(r, p, y);
    EXPECT_NEAR(p, pitch, 1e-6);
    expectNear(Transform(0, 0, 0, r, p, y), t, 1e-6);
  }
}

TEST(Transform, AlgebraMatchesEigen) {
  std::mt19937 rng(rtabmap::test::drawSeed(2));
  for (int i = 0; i < 100; ++i) {
    const Transform a = randomTransform(rng);
    const Transform b = randomTransform(rng);
    const Eigen::Isometry3d ea = a.toEigen(), eb = b.toEigen();
    EXPECT_LE(((a * b).toMatrix4d() - (ea * eb).matrix()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LE((a.inverse().toMatrix4d() - ea.inverse().matrix()).cwiseAbs().maxCoeff(), 1e-12);
    const Eigen::Vector3d p(0.5, -2, 3);
    EXPECT_LE(((a * p) - ea * p).norm(), 1e-12);
    // Identities.
    expectNear(a * a.inverse(), Transform::Identity(), 1e-12);
    expectNear(a.inverse() * a, Transform::Identity(), 1e-12);
    expectNear((a * b).inverse(), b.inverse() * a.inverse(), 1e-12);
    expectNear(a.inverse().inverse(), a, 1e-12);
    Transform c = a;
    c *= b;
    EXPECT_EQ(c, a * b);
    // Relative motion from pose a to pose b, composed back.
    expectNear(a * (a.inverse() * b), b, 1e-11);
  }
}

TEST(Transform, ConstructorsAndAccessors) {
  const Transform t2d(1.5, -2.0, 0.3);
  EXPECT_DOUBLE_EQ(t2d.x(), 1.5);
  EXPECT_DOUBLE_EQ(t2d.y(), -2.0);
  EXPECT_DOUBLE_EQ(t2d.z(), 0.0);
  EXPECT_NEAR(t2d.theta(), 0.3, 1e-15);
  EXPECT_NEAR(t2d.roll(), 0.0, 1e-15);
  EXPECT_NEAR(t2d.pitch(), 0.0, 1e-15);
  expectNear(t2d, Transform(1.5, -2.0, 0, 0, 0, 0.3), 0.0);

  // Quaternion: a non-unit quaternion is normalised.
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const Transform tq(1, 2, 3, 2 * q.x(), 2 * q.y(), 2 * q.z(), 2 * q.w());
  EXPECT_LE((tq.rotationMatrix() - q.toRotationMatrix()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(tq.rotationMatrix().determinant(), 1.0, 1e-12);
  EXPECT_NEAR(tq.quaternion().angularDistance(q), 0.0, 1e-9);
  EXPECT_THROW(Transform(0, 0, 0, 0, 0, 0, 0), std::invalid_argument);

  // 3x4, Matrix4d, Isometry, array12 all agree.
  double a[12];
  tq.toArray12(a);
  expectNear(Transform::fromArray12(a), tq, 0.0);
  expectNear(Transform(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8], a[9], a[10], a[11]), tq, 0.0);
  expectNear(Transform(tq.toMatrix4d()), tq, 0.0);
  expectNear(Transform(tq.toEigen()), tq, 0.0);
  EXPECT_EQ(tq.translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(a[3], 1.0);
  EXPECT_EQ(a[7], 2.0);
  EXPECT_EQ(a[11], 3.0);
  double x, y, z, r, p, yy;
  tq.getTranslationAndEulerAngles(x, y, z, r, p, yy);
  expectNear(Transform(x, y, z, r, p, yy), tq, 1e-12);
}

TEST(Transform, NormsAnglesDistance) {
  const Transform t(3, 4, 12, 0, 0, 0);
  EXPECT_DOUBLE_EQ(t.getNorm(), 13.0);
  EXPECT_DOUBLE_EQ(t.getNorm2D(), 5.0);
  EXPECT_DOUBLE_EQ(t.getDistance(Transform::Identity()), 13.0);
  EXPECT_NEAR(Transform(0, 0, 0, 0.3, 0, 0).getAngle(), 0.3, 1e-12);
  EXPECT_NEAR(Transform(0, 0, 0, 0, 0, -0.3).getAngle(), 0.3, 1e-12);
  EXPECT_NEAR(Transform(0, 0, 0, 0, 0, M_PI).getAngle(), M_PI, 1e-12);
  EXPECT_NEAR(Transform::Identity().getAngle(), 0.0, 1e-15);
  std::mt19937 rng(rtabmap::test::drawSeed(3));
  for (int i = 0; i < 200; ++i) {
    const Transform r = randomTransform(rng);
    const double angle = r.getAngle();
    EXPECT_GE(angle, 0.0);
    EXPECT_LE(angle, M_PI);
    EXPECT_NEAR(angle, Eigen::AngleAxisd(r.rotationMatrix()).angle(), 1e-9);
    EXPECT_NEAR(r.inverse().getAngle(), angle, 1e-9);
  }
}

TEST(Transform, IdentityInvalidAndEquality) {
  EXPECT_TRUE(Transform(0, 0, 0, 0, 0, 1e-12).isIdentity());
  EXPECT_FALSE(Transform(0, 0, 0, 0, 0, 1e-6).isIdentity());
  EXPECT_TRUE(Transform(0, 0, 0, 0, 0, 1e-6).isIdentity(1e-5));
  EXPECT_TRUE(Transform(std::nan(""), 0, 0, 0, 0, 0).isInvalid());
  EXPECT_TRUE(Transform(INFINITY, 0, 0).isInvalid());
  EXPECT_FALSE(Transform(1, 2, 3).isInvalid());
  EXPECT_EQ(Transform(1, 2, 3), Transform(1, 2, 3));
  EXPECT_NE(Transform(1, 2, 3), Transform(1, 2, 3.0000001));
}

TEST(Transform, To3DoF) {
  const Transform t(1, 2, 3, 0.1, -0.2, 0.5);
  const Transform p = t.to3DoF();
  EXPECT_DOUBLE_EQ(p.x(), 1);
  EXPECT_DOUBLE_EQ(p.y(), 2);
  EXPECT_DOUBLE_EQ(p.z(), 0);
  EXPECT_NEAR(p.roll(), 0, 1e-15);
  EXPECT_NEAR(p.pitch(), 0, 1e-15);
  EXPECT_NEAR(p.yaw(), t.yaw(), 1e-15);
}

TEST(Transform, Interpolate) {
  const Transform a(0, 0, 0, 0, 0, 0.2);
  const Transform b(2, 4, -6, 0, 0, 1.0);
  expectNear(a.interpolate(0.0, b), a, 1e-12);
  expectNear(a.interpolate(1.0, b), b, 1e-12);
  const Transform m = a.interpolate(0.25, b);
  EXPECT_NEAR(m.x(), 0.5, 1e-12);
  EXPECT_NEAR(m.y(), 1.0, 1e-12);
  EXPECT_NEAR(m.z(), -1.5, 1e-12);
  EXPECT_NEAR(m.yaw(), 0.4, 1e-12);
  // Slerp takes the short way across +-pi.
  const Transform c(0, 0, 0, 0, 0, 3.0), d(0, 0, 0, 0, 0, -3.0);
  EXPECT_NEAR(std::abs(c.interpolate(0.5, d).yaw()), M_PI, 1e-9);
  // General 3D: matches Eigen's slerp.
  std::mt19937 rng(rtabmap::test::drawSeed(4));
  const Transform e = randomTransform(rng), f = randomTransform(rng);
  const Transform g = e.interpolate(0.3, f);
  EXPECT_NEAR(g.quaternion().angularDistance(e.quaternion().slerp(0.3, f.quaternion())), 0, 1e-9);
}

TEST(Transform, NormalizedReorthonormalises) {
  std::mt19937 rng(rtabmap::test::drawSeed(5));
  const Transform t = randomTransform(rng);
  Eigen::Matrix4d m = t.toMatrix4d();
  // The perturbation from the test's draw too (Eigen's Random() is std::rand, whose state
  // depends on the tests run before this one).
  std::uniform_real_distribution<double> e(-1e-4, 1e-4);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) += e(rng);
  }
  const Transform noisy(m);
  const Transform n = noisy.normalized();
  const Eigen::Matrix3d R = n.rotationMatrix();
  EXPECT_LE((R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
  EXPECT_LE((R - t.rotationMatrix()).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_EQ(n.translation(), noisy.translation());

  // Many float-ish compositions drift; normalized() brings it back.
  Transform acc = Transform::Identity();
  const Transform step(0.01, 0, 0, 0.001, 0.002, 0.003);
  for (int i = 0; i < 10000; ++i) acc = (acc * step);
  const Eigen::Matrix3d Ra = acc.normalized().rotationMatrix();
  EXPECT_LE((Ra * Ra.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Transform, FromStringAcceptedForms) {
  expectNear(Transform::fromString("1 2 0.5"), Transform(1, 2, 0.5), 0.0);
  expectNear(Transform::fromString("1 2 3 0.1 0.2 0.3"), Transform(1, 2, 3, 0.1, 0.2, 0.3), 0.0);
  expectNear(Transform::fromString("  1\t2\n3 0.1 0.2 0.3 "), Transform(1, 2, 3, 0.1, 0.2, 0.3), 0.0);
  expectNear(Transform::fromString("1,2,3,0.1,0.2,0.3"), Transform(1, 2, 3, 0.1, 0.2, 0.3), 0.0);
  expectNear(Transform::fromString("1 2 3 0 0 0 1"), Transform(1, 2, 3, 0, 0, 0), 0.0);
  expectNear(Transform::fromString("0 0 0 0 0 0.7071067811865476 0.7071067811865476"),
             Transform(0, 0, 0, 0, 0, M_PI / 2), 1e-12);
  expectNear(Transform::fromString("1 0 0 4 0 1 0 5 0 0 1 6"), Transform(4, 5, 6, 0, 0, 0), 0.0);
  expectNear(Transform::fromString("1e-3 -2E2 +3 0 0 0"), Transform(0.001, -200, 3, 0, 0, 0), 0.0);
  EXPECT_TRUE(Transform::fromString("null").isNull());
}

TEST(Transform, FromStringRejects) {
  for (const std::string bad :
       {"", "1 2", "a b c", "nan 0 0", "1 2 inf", "1 2 3 4", "1 2 3 4 5", "1 2 3 4 5 6 7 8",
        "1 2 3x", "0 0 0 0 0 0 0", "null 1", "1e999 0 0", "+ 1 2", "1 2 --3", "1 2 3 4 5 6 7 8 9 10 11"}) {
    try {
      Transform::fromString(bad);
      ADD_FAILURE() << "accepted \"" << bad << "\"";
    } catch (const FormatError& e) {
      // The message names the string.
      EXPECT_NE(std::string(e.what()).find("\"" + bad + "\""), std::string::npos) << e.what();
    }
  }
}

TEST(Transform, ToStringRoundTrips) {
  std::mt19937 rng(rtabmap::test::drawSeed(6));
  for (int i = 0; i < 200; ++i) {
    const Transform t = randomTransform(rng);
    const std::string s = t.toString();
    const Transform back = Transform::fromString(s);
    // Only the Euler <-> matrix conversion rounds: within a few ulps.
    expectNear(back, t, 1e-14 * 20);
    // Second pass is a fixed point in translation, exactly.
    EXPECT_EQ(back.translation(), t.translation());
  }
  EXPECT_TRUE(Transform::fromString(Transform().toString()).isNull());
  // Exact values survive exactly.
  const Transform exact(0.1, 0.2, 0.3, 0, 0, 0);
  EXPECT_EQ(Transform::fromString(exact.toString()), exact);
}

TEST(Transform, PrettyPrintAndStream) {
  const Transform t(1, 2, 0, 0, 0, M_PI / 2);
  EXPECT_EQ(t.prettyPrint(), "xyz=1.000,2.000,0.000 rpy=0.000,0.000,1.571");
  std::ostringstream os;
  os << t;
  EXPECT_EQ(os.str(), t.prettyPrint());
}

TEST(Transform, OpticalFrameConventionExample) {
  // A camera 1 m forward looking along the base x axis: a point 2 m in front of the camera
  // (optical z) is 3 m in front of the robot.
  const Transform camera = Transform(1, 0, 0, 0, 0, 0) *
                           Transform(0, 0, 1, 0, -1, 0, 0, 0, 0, -1, 0, 0);
  const Eigen::Vector3d p = camera * Eigen::Vector3d(0, 0, 2);
  EXPECT_NEAR(p.x(), 3, 1e-12);
  EXPECT_NEAR(p.y(), 0, 1e-12);
  EXPECT_NEAR(p.z(), 0, 1e-12);
}

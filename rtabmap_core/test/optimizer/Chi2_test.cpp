// chi2 in g2o's convention on tiny examples computed by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "rtabmap_core/optimizer/Chi2.h"
#include "rtabmap_core/optimizer/GraphIO.h"

namespace rtabmap {
namespace {

TEST(Chi2, Se2ByHand) {
  // X0 = identity, X1 = (1, 0, 0.1), Z = (1.1, -0.2, 0): E = Z^-1 X1 = (-0.1, 0.2, 0.1).
  std::map<int, Transform> poses{{0, Transform(0, 0, 0)}, {1, Transform(1, 0, 0.1)}};
  Eigen::Matrix3d info;
  info << 2, 0.5, 0, 0.5, 3, 0, 0, 0, 4;
  std::multimap<int, Link> links;
  links.emplace(0, Link(0, 1, Link::kNeighbor, Transform(1.1, -0.2, 0.0),
                        graph::linkInformationFromSE2(info)));
  const Eigen::Vector3d e = graph::errorSE2(poses[0], poses[1], Transform(1.1, -0.2, 0.0));
  EXPECT_NEAR(e[0], -0.1, 1e-12);
  EXPECT_NEAR(e[1], 0.2, 1e-12);
  EXPECT_NEAR(e[2], 0.1, 1e-12);
  // 2 * 0.01 + 3 * 0.04 + 4 * 0.01 + 2 * 0.5 * (-0.1 * 0.2) = 0.16
  EXPECT_NEAR(graph::computeChi2(poses, links, true), 0.16, 1e-12);
  // Identity information: 0.01 + 0.04 + 0.01.
  EXPECT_NEAR(graph::computeChi2(poses, links, true, true), 0.06, 1e-12);
}

TEST(Chi2, Se2ThetaIsWrapped) {
  // theta_j - theta_i - theta_z = 3.0 - 0 - (-3.0) = 6.0 -> 6.0 - 2 pi.
  const Eigen::Vector3d e =
      graph::errorSE2(Transform(0, 0, 0), Transform(0, 0, 3.0), Transform(0, 0, -3.0));
  EXPECT_NEAR(e[2], 6.0 - 2 * M_PI, 1e-12);
}

TEST(Chi2, Se2ErrorIsInTheMeasurementFrame) {
  // X1 = (0, 1, pi/2) seen from X0 = identity, Z = (0, 1.5, pi/2): Z^-1 X1 has translation
  // R(-pi/2) (0, -0.5) = (-0.5, 0).
  const Eigen::Vector3d e = graph::errorSE2(Transform(0, 0, 0), Transform(0, 1, M_PI / 2),
                                            Transform(0, 1.5, M_PI / 2));
  EXPECT_NEAR(e[0], -0.5, 1e-12);
  EXPECT_NEAR(e[1], 0.0, 1e-12);
  EXPECT_NEAR(e[2], 0.0, 1e-12);
}

TEST(Chi2, Se3UsesTheQuaternionVectorNotTheAngle) {
  // X1 = translation (1, 2, 3), rotation 0.2 rad about z; Z = translation (1, 2, 2.5), no
  // rotation. E = (0, 0, 0.5) and a rotation of 0.2 about z: qvec = (0, 0, sin(0.1)).
  // Link information (per radian): 2 on z, 1 on yaw -> g2o weighs qz by 4.
  std::map<int, Transform> poses{{0, Transform::Identity()},
                                 {1, Transform(1, 2, 3, 0, 0, 0.2)}};
  Link::InfMatrix info = Link::InfMatrix::Identity();
  info(2, 2) = 2;
  std::multimap<int, Link> links;
  links.emplace(0, Link(0, 1, Link::kNeighbor, Transform(1, 2, 2.5, 0, 0, 0), info));
  const double expected = 2 * 0.25 + 4 * std::sin(0.1) * std::sin(0.1);
  EXPECT_NEAR(graph::computeChi2(poses, links, false), expected, 1e-12);
  // 0.2 rad would give 0.04 on yaw with the angle convention: the g2o one is 4 sin^2(0.1).
  EXPECT_GT(std::fabs(graph::computeChi2(poses, links, false) - (0.5 + 0.04)), 1e-5);

  // The same rotation with the opposite quaternion sign gives the same error (w >= 0).
  const Transform flipped(1, 2, 2.5, 0, 0, 0.0, -1.0);
  const graph::Vector6 e = graph::errorSE3(poses[0], poses[1], flipped);
  EXPECT_NEAR(e[5], std::sin(0.1), 1e-12);
}

TEST(Chi2, G2oFileInformationIsPerQuaternionUnit) {
  // The same example as a g2o file: rotation information 4 on qz in the file is 1 per radian
  // in the Link, and the chi2 comes back in g2o's convention.
  std::istringstream text(
      "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n"
      "VERTEX_SE3:QUAT 1 1 2 3 0 0 0.099833416646828155 0.99500416527802582\n"
      "EDGE_SE3:QUAT 0 1 1 2 2.5 0 0 0 1  1 0 0 0 0 0  1 0 0 0 0  2 0 0 0  4 0 0  4 0  4\n");
  const graph::PoseGraphFile file = graph::parseG2o(text, "tiny.g2o");
  ASSERT_EQ(file.links.size(), 1u);
  EXPECT_NEAR(file.links.begin()->second.infMatrix()(5, 5), 1.0, 1e-12);
  EXPECT_NEAR(file.links.begin()->second.infMatrix()(2, 2), 2.0, 1e-12);
  EXPECT_NEAR(graph::computeChi2(file.poses, file.links, false),
              2 * 0.25 + 4 * std::sin(0.1) * std::sin(0.1), 1e-12);
}

TEST(Chi2, InformationConversionsRoundTrip) {
  Link::InfMatrix info = Link::InfMatrix::Identity();
  info.diagonal() << 1, 2, 3, 4, 5, 6;
  info(1, 4) = info(4, 1) = 0.5;
  info(3, 5) = info(5, 3) = 0.25;
  const graph::Matrix6 g2o = graph::informationSE3ToG2o(info);
  EXPECT_DOUBLE_EQ(g2o(3, 3), 16);   // rotation x 4
  EXPECT_DOUBLE_EQ(g2o(1, 4), 1.0);  // cross x 2
  EXPECT_DOUBLE_EQ(g2o(3, 5), 1.0);
  EXPECT_LT((graph::informationSE3FromG2o(g2o) - info).cwiseAbs().maxCoeff(), 1e-15);

  const Eigen::Matrix3d se2 = graph::informationSE2(info);
  EXPECT_DOUBLE_EQ(se2(0, 0), 1);
  EXPECT_DOUBLE_EQ(se2(2, 2), 6);
  const Link::InfMatrix back = graph::linkInformationFromSE2(se2, 7.0);
  EXPECT_DOUBLE_EQ(back(5, 5), 6);
  EXPECT_DOUBLE_EQ(back(2, 2), 7);
  EXPECT_DOUBLE_EQ(back(3, 3), 7);
  EXPECT_DOUBLE_EQ(back(0, 5), 0);
}

TEST(Chi2, PriorsCountAndAbsentNodesDoNot) {
  std::map<int, Transform> poses{{1, Transform(1, 0, 0)}};
  std::multimap<int, Link> links;
  links.emplace(1, Link(1, 1, Link::kPosePrior, Transform(0, 0, 0), Link::InfMatrix::Identity()));
  links.emplace(1, Link(1, 2, Link::kNeighbor, Transform(1, 0, 0), Link::InfMatrix::Identity()));
  EXPECT_NEAR(graph::computeChi2(poses, links, true), 1.0, 1e-12);
}

}  // namespace
}  // namespace rtabmap

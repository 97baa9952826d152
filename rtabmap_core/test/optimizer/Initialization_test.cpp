// Spanning-tree and chordal initialisation.
#include <gtest/gtest.h>

#include <iterator>
#include <set>

#include "SyntheticGraph.h"
#include "rtabmap_core/optimizer/Chi2.h"
#include "rtabmap_core/optimizer/Initialization.h"

namespace rtabmap {
namespace {

using test::makeSquareLoops;
using test::maxPositionError;
using test::NoiseModel;

NoiseModel noiseless() {
  NoiseModel n;
  n.sigmaXY = n.sigmaZ = 1e-12;
  n.sigmaAngle = 1e-12;
  return n;
}

TEST(Initialization, ExactGraphsAreRecoveredByBothMethods) {
  for (bool is2D : {true, false}) {
    const auto g = makeSquareLoops(2, 5, is2D, noiseless(), 1, 1, 0.5);
    // Information from a realistic model, measurements exact.
    std::multimap<int, Link> links;
    for (const auto& [k, l] : g.links) {
      links.emplace(k, Link(l.from(), l.to(), l.type(), l.transform(),
                            test::informationOf(NoiseModel(), is2D)));
    }
    const int root = g.truth.rbegin()->first;
    const auto tree = graph::spanningTreeInitialization(root, g.truth.at(root), links, is2D);
    std::string why;
    const auto chordal = graph::chordalInitialization(root, g.truth.at(root), links, is2D, false, &why);
    ASSERT_EQ(tree.size(), g.truth.size());
    ASSERT_EQ(chordal.size(), g.truth.size()) << why;
    for (const auto& [id, pose] : g.truth) {
      EXPECT_LT((tree.at(id).toMatrix4d() - pose.toMatrix4d()).cwiseAbs().maxCoeff(), 1e-9) << id;
      EXPECT_LT((chordal.at(id).toMatrix4d() - pose.toMatrix4d()).cwiseAbs().maxCoeff(), 1e-9) << id;
    }
  }
}

TEST(Initialization, TheRootKeepsItsPose) {
  const auto g = makeSquareLoops(1, 3, false, noiseless(), 2, 10);
  const Transform rootPose(5, -2, 1, 0.3, -0.1, 2.0);
  const auto chordal = graph::chordalInitialization(20, rootPose, g.links, false);
  ASSERT_TRUE(chordal.count(20));
  EXPECT_LT((chordal.at(20).toMatrix4d() - rootPose.toMatrix4d()).cwiseAbs().maxCoeff(), 1e-12);
  // Others follow: 10 relative to 20 as in the truth.
  const Transform expected = rootPose * g.truth.at(20).inverse() * g.truth.at(10);
  EXPECT_LT((chordal.at(10).toMatrix4d() - expected.toMatrix4d()).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Initialization, ChordalBeatsTheTreeOnANoisyGraph) {
  // With rotation noise, a spanning tree accumulates drift along its branches; the chordal
  // estimate spreads it over the loops.
  NoiseModel noise;
  noise.sigmaXY = 0.02;
  noise.sigmaAngle = 0.03;
  for (bool is2D : {true, false}) {
    const auto g = makeSquareLoops(4, 10, is2D, noise, 3, 1, 0.5);
    const int root = 1;
    const auto tree = graph::spanningTreeInitialization(root, g.truth.at(root), g.links, is2D,
                                                        /*odometryFirst=*/true);
    const auto chordal = graph::chordalInitialization(root, g.truth.at(root), g.links, is2D);
    ASSERT_EQ(chordal.size(), g.truth.size());
    const double treeChi2 = graph::computeChi2(tree, g.links, is2D);
    const double chordalChi2 = graph::computeChi2(chordal, g.links, is2D);
    EXPECT_LT(chordalChi2, 0.1 * treeChi2) << (is2D ? "2D" : "3D");
    EXPECT_LT(maxPositionError(g.truth, chordal, root), maxPositionError(g.truth, tree, root));
  }
}

TEST(Initialization, OdometryFirstFollowsTheOdometryChain) {
  // 1-2-3 by odometry, and a loop closure 1-3 that disagrees: odometry first reaches 3 through
  // 2; plain breadth-first reaches it directly through the loop closure.
  std::multimap<int, Link> links;
  links.emplace(1, Link(1, 2, Link::kNeighbor, Transform(1, 0, 0)));
  links.emplace(2, Link(2, 3, Link::kNeighbor, Transform(1, 0, 0)));
  links.emplace(1, Link(1, 3, Link::kGlobalClosure, Transform(3, 0, 0)));
  const auto odom = graph::spanningTreeInitialization(1, Transform(), links, true, true);
  const auto bfs = graph::spanningTreeInitialization(1, Transform(), links, true, false);
  EXPECT_NEAR(odom.at(3).x(), 2.0, 1e-12);
  EXPECT_NEAR(bfs.at(3).x(), 3.0, 1e-12);
  EXPECT_TRUE(odom.at(1).isIdentity());  // null root pose -> identity
}

TEST(Initialization, KnownPosesAreKeptAndTheRestComposed) {
  std::multimap<int, Link> links;
  links.emplace(1, Link(1, 2, Link::kNeighbor, Transform(1, 0, 0)));
  links.emplace(2, Link(2, 3, Link::kNeighbor, Transform(1, 0, 0)));
  links.emplace(3, Link(3, 4, Link::kNeighbor, Transform(0, 1, 0)));
  const std::map<int, Transform> known{{1, Transform(10, 0, 0)}, {3, Transform(20, 5, 0)}};
  const auto poses = graph::spanningTreeInitialization(1, Transform(), links, true, true, &known);
  EXPECT_NEAR(poses.at(1).x(), 10, 1e-12);
  EXPECT_NEAR(poses.at(2).x(), 11, 1e-12);  // composed
  EXPECT_NEAR(poses.at(3).x(), 20, 1e-12);  // kept
  EXPECT_NEAR(poses.at(4).y(), 6, 1e-12);   // composed from the kept one
}

// Every node known (the SLAM update's case): the same poses as the tree, bit for bit, in 2D
// (x, y, yaw: the input's z, roll and pitch are not the tree's) and 3D; empty when one is missing.
TEST(Initialization, KnownPosesWithoutTheTreeAreTheTreesPoses) {
  NoiseModel noise;
  noise.sigmaXY = 0.05;
  noise.sigmaAngle = 0.05;
  for (bool is2D : {true, false}) {
    const auto g = makeSquareLoops(2, 6, is2D, noise, 7, 1, 0.5);
    std::map<int, Transform> known;
    std::set<int> nodes;
    for (const auto& [id, pose] : g.odometry) {
      known.emplace(id, pose * Transform(0, 0, 0.1, 0.02, -0.03, 0));  // off the plane too
      nodes.insert(id);
    }
    const int root = g.odometry.begin()->first;
    const auto tree = graph::spanningTreeInitialization(root, Transform(), g.links, is2D, true, &known);
    const auto direct = graph::knownPosesInitialization(nodes, known, is2D);
    ASSERT_EQ(direct.size(), tree.size());
    for (const auto& [id, pose] : tree) {
      ASSERT_TRUE(direct.count(id)) << id;
      EXPECT_EQ(direct.at(id).toMatrix4d(), pose.toMatrix4d()) << id << (is2D ? " 2D" : " 3D");
    }
    known.erase(std::next(known.begin(), 3));
    EXPECT_TRUE(graph::knownPosesInitialization(nodes, known, is2D).empty());
    known.emplace(std::next(g.odometry.begin(), 3)->first, Transform());  // null: not known either
    EXPECT_TRUE(graph::knownPosesInitialization(nodes, known, is2D).empty());
  }
}

TEST(Initialization, OnlyTheRootComponentAndBackwardLinks) {
  std::multimap<int, Link> links;
  links.emplace(2, Link(2, 1, Link::kNeighbor, Transform(-1, 0, 0)));  // walked backwards
  links.emplace(5, Link(5, 6, Link::kNeighbor, Transform(1, 0, 0)));   // another component
  for (const auto& poses : {graph::spanningTreeInitialization(1, Transform(), links, false),
                            graph::chordalInitialization(1, Transform(), links, false)}) {
    ASSERT_EQ(poses.size(), 2u);
    EXPECT_NEAR(poses.at(2).x(), 1.0, 1e-12);
    EXPECT_FALSE(poses.count(5));
  }
  // A lone root.
  const auto alone = graph::chordalInitialization(9, Transform(1, 2, 3), links, true);
  ASSERT_EQ(alone.size(), 1u);
  EXPECT_NEAR(alone.at(9).x(), 1.0, 1e-12);
}

}  // namespace
}  // namespace rtabmap

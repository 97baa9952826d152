// optimizeGraph(): synthetic graphs recover the truth, multi-session roots, failures keep the
// input, options.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "SyntheticGraph.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/optimizer/Chi2.h"
#include "rtabmap_core/optimizer/Optimizer.h"

namespace rtabmap {
namespace {

using test::makeSquareLoops;
using test::maxPositionError;
using test::NoiseModel;

OptimizerOptions options2D() {
  OptimizerOptions o;
  o.force3DoF = true;
  return o;
}

bool allFinite(const std::map<int, Transform>& poses) {
  for (const auto& [id, pose] : poses) {
    (void)id;
    if (pose.isNull() || pose.isInvalid()) return false;
  }
  return true;
}

TEST(Optimizer, Se2NoisyLoopsRecoverTheTruth) {
  NoiseModel noise;
  noise.sigmaXY = 0.01;
  noise.sigmaAngle = 0.003;
  const auto g = makeSquareLoops(3, 10, true, noise, 11);
  const int root = g.truth.rbegin()->first;
  std::map<int, Transform> first;  // the estimate from the first initialisation
  for (GraphInitialization init : {GraphInitialization::kInputPoses,
                                   GraphInitialization::kSpanningTree,
                                   GraphInitialization::kChordal}) {
    OptimizerOptions o = options2D();
    o.initialization = init;
    OptimizerSummary summary;
    // Odometry poses, expressed so that the root starts at its true pose.
    std::map<int, Transform> input;
    const Transform align = g.truth.at(root) * g.odometry.at(root).inverse();
    for (const auto& [id, pose] : g.odometry) input.emplace(id, align * pose);
    const auto out = optimizeGraph(o, input, g.links, &summary);
    ASSERT_TRUE(summary.success) << summary.why;
    EXPECT_TRUE(summary.converged) << summary.why;
    EXPECT_EQ(summary.rootId, root);
    EXPECT_TRUE(summary.rootFixed);
    EXPECT_TRUE(summary.is2D);
    EXPECT_EQ(summary.nodes, static_cast<int>(g.truth.size()));
    EXPECT_EQ(summary.links, static_cast<int>(g.links.size()));
    EXPECT_FALSE(summary.otherComponentsLeftOut);
    EXPECT_LT(summary.finalChi2, summary.initialChi2 + 1e-9);
    EXPECT_NEAR(summary.finalChi2, graph::computeChi2(out, g.links, true), 1e-6 * summary.finalChi2);
    ASSERT_EQ(out.size(), g.truth.size());
    // The root did not move; the drift of odometry (metres) is gone.
    EXPECT_LT((out.at(root).toMatrix4d() - g.truth.at(root).toMatrix4d()).cwiseAbs().maxCoeff(), 1e-9);
    const double odometryError = maxPositionError(g.truth, input, root);
    const double optimisedError = maxPositionError(g.truth, out, root);
    // The maximum-likelihood estimate is not the truth, and how far it stays is a draw's luck:
    // over 100 draws of this noise the odometry drifted 0.16-0.68 m and the estimate kept
    // 0.04-0.16 m of error (up to 0.8 of a small drift). Bounds that hold for any draw, not for
    // this one: the optimum from every initialisation, chi2 near the redundancy.
    EXPECT_GT(odometryError, 0.1);
    EXPECT_LT(optimisedError, 0.25) << initializationName(init);
    // The same optimum from every initialisation: the solver found the minimum, not a start's
    // neighbourhood.
    if (first.empty()) first = out;
    EXPECT_LT(maxPositionError(first, out, root), 1e-3) << initializationName(init);
    // At the optimum, chi2 is about the redundancy: residuals minus free parameters (here 240
    // degrees of freedom, a standard deviation of sqrt(2 * 240) = 22, so +-40% is 4 of them).
    const double dof = 3.0 * g.links.size() - 3.0 * (g.truth.size() - 1);
    EXPECT_GT(summary.finalChi2, 0.6 * dof);
    EXPECT_LT(summary.finalChi2, 1.4 * dof);
  }
}

TEST(Optimizer, Se3NoisyLoopsRecoverTheTruth) {
  NoiseModel noise;
  noise.sigmaXY = noise.sigmaZ = 0.01;
  noise.sigmaAngle = 0.003;
  const auto g = makeSquareLoops(3, 8, false, noise, 12, 1, 0.5);
  const int root = g.truth.rbegin()->first;
  std::map<int, Transform> input;
  const Transform align = g.truth.at(root) * g.odometry.at(root).inverse();
  for (const auto& [id, pose] : g.odometry) input.emplace(id, align * pose);
  for (bool autoDiff : {false, true}) {
    OptimizerOptions o;
    o.autoDiff = autoDiff;
    OptimizerSummary summary;
    const auto out = optimizeGraph(o, input, g.links, &summary);
    ASSERT_TRUE(summary.success) << summary.why;
    EXPECT_FALSE(summary.is2D);
    const double odometryError = maxPositionError(g.truth, input, root);
    const double optimisedError = maxPositionError(g.truth, out, root);
    // As in 2D, bounds for any draw of this noise (over 100 draws: drift 0.20-0.74 m, the
    // estimate 0.03-0.15 m off).
    EXPECT_GT(odometryError, 0.1);
    EXPECT_LT(optimisedError, 0.25);
    // chi2 near the redundancy; in g2o's convention the rotation weighs the quaternion vector,
    // which is half the angle, with 4x the information: same chi2 to first order.
    const double dof = 6.0 * g.links.size() - 6.0 * (g.truth.size() - 1);
    EXPECT_GT(summary.finalChi2, 0.6 * dof);
    EXPECT_LT(summary.finalChi2, 1.4 * dof);
    // Orientation recovered too.
    for (const auto& [id, pose] : g.truth) {
      EXPECT_LT((pose.inverse() * out.at(id)).getAngle(), 0.05) << id;
    }
    EXPECT_NEAR(summary.finalChi2, graph::computeChi2(out, g.links, false), 1e-6 * summary.finalChi2);
  }
}

TEST(Optimizer, AnalyticAndAutoDiffReachTheSameOptimum) {
  NoiseModel noise;
  const auto g = makeSquareLoops(2, 6, false, noise, 13, 1, 0.3);
  OptimizerOptions a, b;
  b.autoDiff = true;
  OptimizerSummary sa, sb;
  const auto pa = optimizeGraph(a, g.odometry, g.links, &sa);
  const auto pb = optimizeGraph(b, g.odometry, g.links, &sb);
  ASSERT_TRUE(sa.success && sb.success);
  EXPECT_NEAR(sa.finalChi2, sb.finalChi2, 1e-6 * sa.finalChi2);
  for (const auto& [id, pose] : pa) {
    EXPECT_LT((pose.toMatrix4d() - pb.at(id).toMatrix4d()).cwiseAbs().maxCoeff(), 1e-5);
  }
}

// Two sessions, each in its own odometry frame (session 2 starts at the origin again), the
// second one 100 ids later. One loop closure joins them.
struct TwoSessions {
  test::SyntheticGraph s1, s2;
  std::map<int, Transform> input;
  std::multimap<int, Link> links;
  Link bridge;
};

TwoSessions makeTwoSessions(bool withBridge) {
  NoiseModel noise;
  noise.sigmaXY = 0.02;
  noise.sigmaAngle = 0.005;
  TwoSessions t;
  t.s1 = makeSquareLoops(2, 5, true, noise, 21, 1);
  t.s2 = makeSquareLoops(2, 5, true, noise, 22, 101);
  // Session 2 truly starts at (2, 3, 0.5) of session 1's world.
  const Transform offset(2, 3, 0.5);
  for (auto& [id, pose] : t.s2.truth) pose = offset * pose;
  t.input = t.s1.odometry;
  for (const auto& [id, pose] : t.s2.odometry) t.input.emplace(id, pose);  // own frame
  t.links = t.s1.links;
  t.links.insert(t.s2.links.begin(), t.s2.links.end());
  const Transform rel = t.s2.truth.at(103).inverse() * t.s1.truth.at(7);
  t.bridge = Link(103, 7, Link::kGlobalClosure, rel, test::informationOf(noise, true));
  if (withBridge) t.links.emplace(103, t.bridge);
  return t;
}

TEST(Optimizer, SessionsJoinedByOneLoopClosureEndInOneReferential) {
  const TwoSessions t = makeTwoSessions(true);
  OptimizerSummary summary;
  const auto out = optimizeGraph(options2D(), t.input, t.links, &summary);
  ASSERT_TRUE(summary.success) << summary.why;
  // Root: the most recent node (session 2's last), fixed at its input pose (its odometry).
  const int root = t.s2.truth.rbegin()->first;
  EXPECT_EQ(summary.rootId, root);
  EXPECT_FALSE(summary.otherComponentsLeftOut);
  EXPECT_EQ(out.size(), t.s1.truth.size() + t.s2.truth.size());
  EXPECT_LT((out.at(root).toMatrix4d() - t.input.at(root).toMatrix4d()).cwiseAbs().maxCoeff(), 1e-9);
  // Both sessions now agree with the truth, in the root's frame, up to what one noisy link
  // between them allows (over 100 draws: 0.05-0.19 m at the far end of session 1).
  std::map<int, Transform> truth = t.s1.truth;
  truth.insert(t.s2.truth.begin(), t.s2.truth.end());
  EXPECT_LT(maxPositionError(truth, out, root), 0.3);
  // Session 1 was moved into session 2's odometry frame: node 1 is no longer at its input.
  EXPECT_GT(out.at(1).getDistance(t.input.at(1)), 1.0);
}

TEST(Optimizer, WithoutTheBridgeOnlyTheRootsComponentIsOptimised) {
  const TwoSessions t = makeTwoSessions(false);
  OptimizerSummary summary;
  const auto out = optimizeGraph(options2D(), t.input, t.links, &summary);
  ASSERT_TRUE(summary.success) << summary.why;
  EXPECT_EQ(summary.rootId, t.s2.truth.rbegin()->first);
  EXPECT_TRUE(summary.otherComponentsLeftOut);
  EXPECT_EQ(summary.nodesOutsideRootComponent, static_cast<int>(t.s1.truth.size()));
  EXPECT_EQ(summary.linksOutsideRootComponent, static_cast<int>(t.s1.links.size()));
  EXPECT_EQ(summary.nodes, static_cast<int>(t.s2.truth.size()));
  EXPECT_EQ(out.size(), t.s2.truth.size());
  EXPECT_FALSE(out.count(1));
  // An explicit root picks the other session.
  OptimizerSummary other;
  const auto first = optimizeGraph(options2D(), t.input, t.links, &other, 1);
  ASSERT_TRUE(other.success);
  EXPECT_EQ(first.size(), t.s1.truth.size());
  EXPECT_TRUE(first.count(1));
}

TEST(Optimizer, LinksToNodesInLongTermMemoryAreIgnoredAndCounted) {
  const auto g = makeSquareLoops(2, 4, true, NoiseModel(), 31);
  std::map<int, Transform> input = g.odometry;
  // Nodes 5 and 6 were transferred to long-term memory: their links stay in the map.
  input.erase(5);
  input.erase(6);
  int touching = 0;
  for (const auto& [k, l] : g.links) touching += (l.from() == 5 || l.to() == 5 || l.from() == 6 || l.to() == 6);
  OptimizerSummary summary;
  const auto out = optimizeGraph(options2D(), input, g.links, &summary);
  ASSERT_TRUE(summary.success) << summary.why;
  EXPECT_EQ(summary.linksToAbsentNodes, touching);
  EXPECT_FALSE(out.count(5));
  EXPECT_TRUE(allFinite(out));
}

TEST(Optimizer, InvalidInputKeepsTheInputPosesAndSaysWhy) {
  const auto g = makeSquareLoops(1, 4, true, NoiseModel(), 41);
  // A loop closure with a NaN transform.
  auto links = g.links;
  Eigen::Matrix4d bad = Eigen::Matrix4d::Identity();
  bad(0, 3) = std::numeric_limits<double>::quiet_NaN();
  links.emplace(3, Link(3, 9, Link::kGlobalClosure, Transform(bad)));
  OptimizerSummary summary;
  auto out = optimizeGraph(options2D(), g.odometry, links, &summary);
  EXPECT_FALSE(summary.success);
  EXPECT_NE(summary.why.find("3->9"), std::string::npos) << summary.why;
  EXPECT_EQ(out, g.odometry);

  // A non positive-definite information matrix.
  links = g.links;
  Link::InfMatrix info = Link::InfMatrix::Identity();
  info(5, 5) = -1;
  links.emplace(3, Link(3, 9, Link::kGlobalClosure, Transform(0, 0, 0), info));
  out = optimizeGraph(options2D(), g.odometry, links, &summary);
  EXPECT_FALSE(summary.success);
  EXPECT_NE(summary.why.find("positive definite"), std::string::npos) << summary.why;
  EXPECT_EQ(out, g.odometry);

  // A root that does not exist.
  out = optimizeGraph(options2D(), g.odometry, g.links, &summary, 999);
  EXPECT_FALSE(summary.success);
  EXPECT_NE(summary.why.find("999"), std::string::npos);
  EXPECT_EQ(out, g.odometry);

  // Empty graph.
  out = optimizeGraph(options2D(), {}, {}, &summary);
  EXPECT_FALSE(summary.success);
  EXPECT_NE(summary.why.find("empty"), std::string::npos);

  // A non-finite input pose.
  auto input = g.odometry;
  Eigen::Matrix4d nanPose = Eigen::Matrix4d::Identity();
  nanPose(1, 3) = std::numeric_limits<double>::infinity();
  input[4] = Transform(nanPose);
  out = optimizeGraph(options2D(), input, g.links, &summary);
  EXPECT_FALSE(summary.success);
  EXPECT_NE(summary.why.find("node 4"), std::string::npos) << summary.why;

  // Invalid options.
  OptimizerOptions o = options2D();
  o.iterations = 0;
  out = optimizeGraph(o, g.odometry, g.links, &summary);
  EXPECT_FALSE(summary.success);
  EXPECT_NE(summary.why.find("Optimizer/Iterations"), std::string::npos);
  EXPECT_EQ(out, g.odometry);
}

TEST(Optimizer, ALoneRootIsReturnedAsIs) {
  std::map<int, Transform> input{{3, Transform(1, 2, 0.3)}};
  OptimizerSummary summary;
  const auto out = optimizeGraph(options2D(), input, {}, &summary);
  EXPECT_TRUE(summary.success);
  EXPECT_EQ(summary.iterations, 0);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out.at(3), input.at(3));
}

TEST(Optimizer, PriorsAnchorTheGraphInsteadOfTheRoot) {
  const auto g = makeSquareLoops(1, 5, true, NoiseModel(), 51);
  auto links = g.links;
  // GPS-like priors on a few nodes, at their true poses shifted by (100, 50).
  const Transform shift(100, 50, 0.0);
  Link::InfMatrix info = Link::InfMatrix::Identity() * 100.0;
  for (int id : {1, 6, 11, 16}) {
    links.emplace(id, Link(id, id, Link::kPosePrior, shift * g.truth.at(id), info));
  }
  OptimizerOptions o = options2D();
  o.priorsIgnored = false;
  OptimizerSummary summary;
  const auto out = optimizeGraph(o, g.odometry, links, &summary);
  ASSERT_TRUE(summary.success) << summary.why;
  EXPECT_FALSE(summary.rootFixed);
  EXPECT_EQ(summary.priors, 4);
  EXPECT_NEAR(out.at(1).x(), 100.0, 0.2);
  EXPECT_NEAR(out.at(1).y(), 50.0, 0.2);

  // Ignored by default: the root stays, priors counted as ignored.
  const auto ignored = optimizeGraph(options2D(), g.odometry, links, &summary);
  EXPECT_TRUE(summary.rootFixed);
  EXPECT_EQ(summary.linksIgnoredByOptions, 4);
  EXPECT_NEAR(ignored.at(20).x(), g.odometry.at(20).x(), 1e-9);
}

TEST(Optimizer, LandmarksAreCreatedAndReturned) {
  // Three nodes on a line observe landmark -1 at (5, 2).
  std::map<int, Transform> input{{1, Transform(0, 0, 0)}, {2, Transform(1, 0, 0)}, {3, Transform(2, 0, 0)}};
  std::multimap<int, Link> links;
  links.emplace(1, Link(1, 2, Link::kNeighbor, Transform(1, 0, 0)));
  links.emplace(2, Link(2, 3, Link::kNeighbor, Transform(1, 0, 0)));
  for (int id : {1, 2, 3}) {
    const Transform observed = input.at(id).inverse() * Transform(5, 2, 0.0);
    links.emplace(id, Link(id, -1, Link::kLandmark, observed));
  }
  OptimizerSummary summary;
  auto out = optimizeGraph(options2D(), input, links, &summary);
  ASSERT_TRUE(summary.success) << summary.why;
  ASSERT_TRUE(out.count(-1));
  EXPECT_NEAR(out.at(-1).x(), 5.0, 1e-6);
  EXPECT_NEAR(out.at(-1).y(), 2.0, 1e-6);
  EXPECT_EQ(summary.rootId, 3);

  OptimizerOptions o = options2D();
  o.landmarksIgnored = true;
  out = optimizeGraph(o, input, links, &summary);
  EXPECT_FALSE(out.count(-1));
  EXPECT_EQ(summary.linksIgnoredByOptions, 3);
}

TEST(Optimizer, EachComponentUsesItsLandmarksWithoutJoiningThroughThem) {
  // Component {1, 2, 3}: odometry says node 3 is at x = 2.5, the landmark seen from 1 and 3 at
  // (5, 2) says x = 2. Component {10, 11}, elsewhere, sees the same landmark id: it stays apart.
  std::map<int, Transform> input{{1, Transform(0, 0, 0)},   {2, Transform(1.25, 0, 0)}, {3, Transform(2.5, 0, 0)},
                                 {10, Transform(50, 0, 0)}, {11, Transform(51, 0, 0)}};
  std::multimap<int, Link> links;
  const Link::InfMatrix weak = Link::InfMatrix::Identity();
  links.emplace(1, Link(1, 2, Link::kNeighbor, Transform(1.25, 0, 0), weak));
  links.emplace(2, Link(2, 3, Link::kNeighbor, Transform(1.25, 0, 0), weak));
  links.emplace(10, Link(10, 11, Link::kNeighbor, Transform(1, 0, 0), weak));
  const Link::InfMatrix strong = Link::InfMatrix::Identity() * 1e4;
  links.emplace(1, Link(1, -1, Link::kLandmark, Transform(5, 2, 0), strong));
  links.emplace(3, Link(3, -1, Link::kLandmark, Transform(3, 2, 0), strong));
  links.emplace(10, Link(10, -1, Link::kLandmark, Transform(1, 1, 0), strong));
  std::vector<std::string> failures;
  const std::map<int, Transform> out = optimizeEachComponent(options2D(), input, links, &failures);
  EXPECT_TRUE(failures.empty());
  ASSERT_EQ(out.size(), input.size()) << "nodes only";
  EXPECT_NEAR(out.at(1).x(), 0.0, 1e-6) << "the oldest node stays";
  EXPECT_NEAR(out.at(3).x(), 2.0, 0.01) << "the landmark closed the gap";
  EXPECT_NEAR(out.at(10).x(), 50.0, 1e-6) << "not moved to the other component's landmark";
  EXPECT_NEAR(out.at(11).x(), 51.0, 1e-6);
}

TEST(Optimizer, GravityLinksStraightenRollAndPitch) {
  // A chain whose odometry says it tilts: gravity links say it does not.
  std::map<int, Transform> input;
  std::multimap<int, Link> links;
  const Transform step(1, 0, 0, 0.02, 0.03, 0.0);
  Transform pose = Transform::Identity();
  Link::InfMatrix info = Link::InfMatrix::Identity();
  info(3, 3) = info(4, 4) = 1.0;  // weak rotation information
  for (int id = 1; id <= 10; ++id) {
    input.emplace(id, pose);
    if (id > 1) links.emplace(id - 1, Link(id - 1, id, Link::kNeighbor, step, info));
    links.emplace(id, Link(id, id, Link::kGravity, Transform(0, 0, 0, 0, 0, 0.7)));
    pose = pose * step;
  }
  OptimizerOptions o;
  o.gravitySigma = 0.01;
  OptimizerSummary summary;
  const auto out = optimizeGraph(o, input, links, &summary, 1);
  ASSERT_TRUE(summary.success) << summary.why;
  EXPECT_EQ(summary.gravityLinks, 10);  // the fixed root's own gravity link included
  double roll, pitch, yaw;
  out.at(10).getEulerAngles(roll, pitch, yaw);
  EXPECT_LT(std::fabs(roll), 0.02);
  EXPECT_LT(std::fabs(pitch), 0.02);
  input.at(10).getEulerAngles(roll, pitch, yaw);
  EXPECT_GT(std::fabs(roll) + std::fabs(pitch), 0.3);
}

TEST(Optimizer, Force3DoFKeepsTheOtherDegreesOfFreedomOfTheInput) {
  std::map<int, Transform> input{{1, Transform(0, 0, 0.5, 0.01, 0.02, 0.0)},
                                 {2, Transform(1.2, 0, 0.5, 0.01, 0.02, 0.0)}};
  std::multimap<int, Link> links;
  links.emplace(1, Link(1, 2, Link::kNeighbor, Transform(1, 0, 0)));
  OptimizerSummary summary;
  const auto out = optimizeGraph(options2D(), input, links, &summary, 1);
  ASSERT_TRUE(summary.success);
  EXPECT_NEAR(out.at(2).x(), 1.0, 1e-6);
  EXPECT_NEAR(out.at(2).z(), 0.5, 1e-12);
  EXPECT_NEAR(out.at(2).roll(), 0.01, 1e-9);
  EXPECT_NEAR(out.at(2).pitch(), 0.02, 1e-9);
}

TEST(Optimizer, RobustLossSurvivesAWrongLoopClosure) {
  NoiseModel noise;
  noise.sigmaXY = 0.02;
  noise.sigmaAngle = 0.005;
  const auto g = makeSquareLoops(2, 8, true, noise, 61);
  auto links = g.links;
  // A wrong loop closure: 5 m off.
  links.emplace(40, Link(40, 5, Link::kGlobalClosure,
                         g.truth.at(40).inverse() * g.truth.at(5) * Transform(5, 0, 0),
                         test::informationOf(noise, true)));
  const int root = g.truth.rbegin()->first;
  std::map<int, Transform> input;
  const Transform align = g.truth.at(root) * g.odometry.at(root).inverse();
  for (const auto& [id, pose] : g.odometry) input.emplace(id, align * pose);

  for (GraphInitialization init : {GraphInitialization::kInputPoses, GraphInitialization::kChordal}) {
    OptimizerOptions plain = options2D();
    plain.initialization = init;
    OptimizerOptions robust = plain;
    robust.robust = true;
    OptimizerSummary s0, s1, s2;
    // The optimum without the wrong link is what a robust loss should get close to.
    const auto clean = optimizeGraph(plain, input, g.links, &s0);
    const auto bent = optimizeGraph(plain, input, links, &s1);
    const auto good = optimizeGraph(robust, input, links, &s2);
    ASSERT_TRUE(s0.success && s1.success && s2.success);
    const double bentError = maxPositionError(clean, bent, root);
    EXPECT_GT(bentError, 0.5) << initializationName(init);
    // The Cauchy loss also down-weights the good loop closures a little (their errors are
    // about one standard deviation): close to the clean optimum, not on it.
    EXPECT_LT(maxPositionError(clean, good, root), 0.15 * bentError) << initializationName(init);
    robust.robustLoss = RobustLoss::kHuber;
    const auto huber = optimizeGraph(robust, input, links, &s2);
    EXPECT_LT(maxPositionError(clean, huber, root), 0.5 * bentError) << initializationName(init);
  }
}

TEST(Optimizer, VarianceIgnoredWeighsEveryLinkEqually) {
  const auto g = makeSquareLoops(2, 4, true, NoiseModel(), 71);
  OptimizerOptions o = options2D();
  o.varianceIgnored = true;
  OptimizerSummary summary;
  const auto out = optimizeGraph(o, g.odometry, g.links, &summary);
  ASSERT_TRUE(summary.success);
  EXPECT_NEAR(summary.finalChi2, graph::computeChi2(out, g.links, true, true), 1e-9);
}

TEST(Optimizer, TheIterationLimitIsHonoured) {
  const auto g = makeSquareLoops(3, 10, false, NoiseModel(), 81, 1, 1.0);
  OptimizerOptions o;
  o.iterations = 1;
  o.initialization = GraphInitialization::kInputPoses;
  OptimizerSummary summary;
  optimizeGraph(o, g.odometry, g.links, &summary);
  ASSERT_TRUE(summary.success);
  EXPECT_LE(summary.iterations, 1);
  EXPECT_FALSE(summary.converged);
  EXPECT_NE(summary.why.find("iteration limit"), std::string::npos) << summary.why;
}

TEST(OptimizerOptions, FromParametersAndIsValid) {
  const OptimizerOptions defaults = OptimizerOptions::fromParameters({});
  EXPECT_EQ(defaults.iterations, Parameters::defaultOptimizerIterations());
  EXPECT_DOUBLE_EQ(defaults.epsilon, Parameters::defaultOptimizerEpsilon());
  EXPECT_EQ(defaults.initialization, GraphInitialization::kChordal);
  EXPECT_TRUE(defaults.priorsIgnored);
  EXPECT_FALSE(defaults.force3DoF);
  EXPECT_TRUE(defaults.IsValid());

  const OptimizerOptions o = OptimizerOptions::fromParameters({{"Optimizer/Iterations", "7"},
                                                               {"Optimizer/Init", "1"},
                                                               {"Optimizer/Robust", "true"},
                                                               {"Optimizer/RobustLoss", "1"},
                                                               {"Optimizer/RobustWidth", "2.5"},
                                                               {"Optimizer/PriorsIgnored", "false"},
                                                               {"Optimizer/VarianceIgnored", "true"},
                                                               {"Optimizer/GravitySigma", "0.3"},
                                                               {"Reg/Force3DoF", "true"}});
  EXPECT_EQ(o.iterations, 7);
  EXPECT_EQ(o.initialization, GraphInitialization::kSpanningTree);
  EXPECT_TRUE(o.robust);
  EXPECT_EQ(o.robustLoss, RobustLoss::kHuber);
  EXPECT_DOUBLE_EQ(o.robustWidth, 2.5);
  EXPECT_FALSE(o.priorsIgnored);
  EXPECT_TRUE(o.varianceIgnored);
  EXPECT_NEAR(o.gravitySigma, 0.3, 1e-7);
  EXPECT_TRUE(o.force3DoF);
  EXPECT_THROW(OptimizerOptions::fromParameters({{"Optimizer/Init", "7"}}), ParameterError);

  OptimizerOptions bad;
  std::string why;
  bad.robustWidth = 0;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("Optimizer/RobustWidth"), std::string::npos);
  bad = OptimizerOptions();
  bad.epsilon = -1;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("Optimizer/Epsilon"), std::string::npos);
  bad = OptimizerOptions();
  bad.numThreads = 0;
  EXPECT_FALSE(bad.IsValid(&why));

  EXPECT_EQ(initializationFromName("odometry"), GraphInitialization::kInputPoses);
  EXPECT_EQ(initializationFromName("tree"), GraphInitialization::kSpanningTree);
  EXPECT_EQ(initializationFromName("chordal"), GraphInitialization::kChordal);
  EXPECT_FALSE(initializationFromName("best"));
  EXPECT_STREQ(initializationName(GraphInitialization::kChordal), "chordal");
}

}  // namespace
}  // namespace rtabmap

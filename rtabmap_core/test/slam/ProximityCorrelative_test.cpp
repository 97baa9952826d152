// The correlative search of proximity detection is bounded by what the graph knows
// (RGBD/ProximityCorrelativeSigmas, GraphUncertainty.h). Issue 8: on the Intel log, with the
// whole 3 m window, a robot in one corridor was matched into the parallel corridor on the other
// side of a wall (the other corridor's merged scans see the same doors and walls, shifted by the
// corridor's width), although strong links tied the two places through a few metres of graph.
// Each such link was weak enough to pass RGBD/OptimizeMaxError; dozens of them tore the map. A
// bound by chain length (a fixed drift per metre) stopped that but also stopped ACES's real
// corrections, whose short chains went through weak merged-scan links.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <random>

#include "../../src/slam/GraphUncertainty.h"
#include "rtabmap_core/registration/CorrelativeScanMatcher.h"

namespace rtabmap {
namespace {

using Points = std::vector<Eigen::Vector2f>;

void wall(Points& pts, Eigen::Vector2f a, Eigen::Vector2f b) {
  const int n = static_cast<int>((b - a).norm() / 0.02f);
  for (int i = 0; i <= n; ++i) pts.push_back(a + (b - a) * (float(i) / n));
}

// One face of a corridor wall along x at height y, with door recesses 0.9 m wide going `depth`
// metres into the wall (depth < 0: towards -y) at irregular positions, the same on every floor
// plan row: an office corridor, repeated one corridor over.
void corridorFace(Points& pts, float y, float depth) {
  const float doors[] = {3.0f, 7.5f, 10.2f, 14.8f, 18.1f};
  float x = 0.0f;
  for (float d : doors) {
    wall(pts, {x, y}, {d, y});
    wall(pts, {d, y}, {d, y + depth});
    wall(pts, {d, y + depth}, {d + 0.9f, y + depth});
    wall(pts, {d + 0.9f, y + depth}, {d + 0.9f, y});
    x = d + 0.9f;
  }
  wall(pts, {x, y}, {22.0f, y});
}

// Corridor A: y in [0, 2]; a 0.2 m wall; corridor B: y in [2.2, 4.2].
Points corridorA() {
  Points p;
  corridorFace(p, 0.0f, -0.3f);
  corridorFace(p, 2.0f, 0.3f);
  return p;
}
Points corridorB() {
  Points p;
  corridorFace(p, 2.2f, -0.3f);
  corridorFace(p, 4.2f, 0.3f);
  return p;
}

// What a robot at `pose` sees of `world` within `range`, in its frame, with noise.
Points scanFrom(const Points& world, const Eigen::Vector3f& pose, float range, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.0f, 0.01f);
  const float c = std::cos(pose.z()), s = std::sin(pose.z());
  Points out;
  for (size_t i = 0; i < world.size(); i += 2) {
    const Eigen::Vector2f d = world[i] - pose.head<2>();
    if (d.norm() > range) continue;
    const float ex = n(rng), ey = n(rng);  // in this order on every compiler
    out.emplace_back(c * d.x() + s * d.y() + ex, -s * d.x() + c * d.y() + ey);
  }
  return out;
}

// RGBD/ProximityCorrelative* defaults with the 3 m window of issue 8's runs.
CorrelativeOptions proximityOptions(float window) {
  CorrelativeOptions o;
  o.resolution = 0.1f;
  o.linearWindow = window;
  o.angularWindow = 20.0f * static_cast<float>(M_PI) / 180.0f;
  o.minScore = 0.6f;
  o.maxSecondPeakRatio = 0.9f;
  return o;
}

constexpr float kWindow = 3.0f;    // RGBD/ProximityCorrelativeWindow of the runs
constexpr float kIcpReach = 0.3f;  // Icp/MaxCorrespondenceDistance of config/lidar2d.ini
constexpr float kSigmas = 3.0f;    // RGBD/ProximityCorrelativeSigmas default

// Link covariances measured on ACES (config/lidar2d.ini): ICP-refined odometry links of 0.3 m
// have a median standard deviation of 0.07 m and 0.55 deg; merged-scan proximity links get
// RGBD/ProximityMergedScanCovFactor (100) times an ICP covariance: 0.7 m and 5 deg.
constexpr double kStrongSd = 0.07, kStrongYawSd = 0.55 * M_PI / 180.0;
constexpr double kWeakSd = 0.7, kWeakYawSd = 5.0 * M_PI / 180.0;

Link::InfMatrix informationOf(double sd, double yawSd) {
  Link::InfMatrix inf = Link::InfMatrix::Identity() / (yawSd * yawSd);  // z, roll, pitch: as yaw
  inf(0, 0) = inf(1, 1) = 1.0 / (sd * sd);
  return inf;
}

Link linkOf(int from, int to, const Transform& t, double sd, double yawSd, Link::Type type = Link::kNeighbor) {
  return Link(from, to, type, t, informationOf(sd, yawSd));
}

// A graph of links, both ways, as Memory keeps them.
class Graph {
 public:
  void add(const Link& l) {
    links_[l.from()].emplace(l.to(), l);
    links_[l.to()].emplace(l.from(), l.inverse());
  }
  std::function<const std::multimap<int, Link>*(int)> linksOf() const {
    return [this](int id) -> const std::multimap<int, Link>* {
      const auto it = links_.find(id);
      return it == links_.end() ? nullptr : &it->second;
    };
  }

 private:
  std::map<int, std::multimap<int, Link>> links_;
};

// The sigma of `to` relative to `from` in `graph`, infinity when not reached within 100 m.
double sigmaBetween(const Graph& graph, int from, int to) {
  const std::map<int, double> s = graphPositionSigmas(from, 100.0, graph.linksOf());
  const auto it = s.find(to);
  return it == s.end() ? std::numeric_limits<double>::infinity() : it->second;
}

TEST(ProximityCorrelative, TheParallelCorridorIsAFalseMatchTheAmbiguityTestLetsThrough) {
  // The robot is in corridor A; the path the graph puts nearest (2.2 m away) runs along B.
  const Eigen::Vector3f robot(8.4f, 1.0f, 0.05f);
  const Points scan = scanFrom(corridorA(), robot, 8.0f, 1);
  const Points pathB = corridorB();
  // The graph is right: its guess is the true pose.
  const CorrelativeResult whole = matchCorrelative(pathB, scan, robot, proximityOptions(kWindow));
  ASSERT_TRUE(whole.found) << "the scene must reproduce the Intel failure: " << whole.why;
  EXPECT_NEAR(whole.pose.y() - robot.y(), 2.2f, 0.15f) << "matched into corridor B";
  EXPECT_LT(whole.guessScore, 0.3f * whole.score);
}

TEST(ProximityCorrelative, StrongLinksBetweenTheTwinCorridorsRefuseTheLookAlike) {
  const Eigen::Vector3f robot(8.4f, 1.0f, 0.05f);
  const Points scan = scanFrom(corridorA(), robot, 8.0f, 1);
  // The robot left corridor B's path (node 1) through a door a moment ago: 5 m of ICP-refined
  // odometry links (0.3 m each) to where it is now (node 18), turning through the door.
  Graph g;
  for (int i = 1; i < 18; ++i) g.add(linkOf(i, i + 1, Transform(0.3, 0.0, i == 8 || i == 12 ? 0.8 : 0.0), kStrongSd, kStrongYawSd));
  const double sigma = sigmaBetween(g, 18, 1);
  const float window = correlativeWindowFor(sigma, kWindow, kIcpReach, kSigmas);
  EXPECT_LT(window, 1.5f) << "sigma " << sigma;
  EXPECT_GE(window, kIcpReach);
  const CorrelativeResult r = matchCorrelative(corridorB(), scan, robot, proximityOptions(window));
  if (r.found) {
    EXPECT_LT((r.pose.head<2>() - robot.head<2>()).norm(), 0.6f) << "no link into corridor B";
  }
}

TEST(ProximityCorrelative, ALoopClosedOnlyByWeakLinksStillGetsItsCorrection) {
  // Back in corridor A; the graph reaches the path's nearest node (1) through 0.4 m of graph only,
  // but through two merged-scan proximity links (node 2 on another path, then the new node 3):
  // short, and weak. The graph's guess is 1.6 m off along the corridor and 0.4 m across. A bound
  // by chain length (0.3 m + 0.05 m/m) would search 0.32 m and miss it; the covariance knows.
  Graph g;
  g.add(linkOf(1, 2, Transform(0.2, 0.0, 0.0), kWeakSd, kWeakYawSd, Link::kLocalSpaceClosure));
  g.add(linkOf(2, 3, Transform(0.2, 0.0, 0.0), kWeakSd, kWeakYawSd, Link::kLocalSpaceClosure));
  const float window = correlativeWindowFor(sigmaBetween(g, 3, 1), kWindow, kIcpReach, kSigmas);
  EXPECT_GT(window, 2.5f) << "two weak links: a metre of sigma";
  const Eigen::Vector3f robot(8.4f, 1.0f, 0.05f);
  const Points scan = scanFrom(corridorA(), robot, 8.0f, 2);
  const Eigen::Vector3f guess = robot + Eigen::Vector3f(1.6f, -0.4f, 0.08f);
  const CorrelativeResult r = matchCorrelative(corridorA(), scan, guess, proximityOptions(window));
  ASSERT_TRUE(r.found) << r.why;
  EXPECT_LT((r.pose.head<2>() - robot.head<2>()).norm(), 0.15f);
}

TEST(ProximityCorrelative, ALongLoopOfStrongLinksWidensTheWindowToTheWhole) {
  // 150 m of strong links around a loop: heading errors over such lever arms leave metres.
  Graph g;
  const int n = 500;
  for (int i = 1; i < n; ++i) g.add(linkOf(i, i + 1, Transform(0.3, 0.0, 2.0 * M_PI / n), kStrongSd, kStrongYawSd));
  EXPECT_FLOAT_EQ(correlativeWindowFor(sigmaBetween(g, n, 1), kWindow, kIcpReach, kSigmas), kWindow);
}

TEST(ProximityCorrelative, WindowIsSigmasStandardDeviationsBetweenIcpReachAndTheWholeWindow) {
  EXPECT_FLOAT_EQ(correlativeWindowFor(0.0, kWindow, kIcpReach, kSigmas), kIcpReach);
  EXPECT_FLOAT_EQ(correlativeWindowFor(0.2, kWindow, kIcpReach, kSigmas), 0.6f);
  EXPECT_FLOAT_EQ(correlativeWindowFor(5.0, kWindow, kIcpReach, kSigmas), kWindow);
  // Not reachable through the links in memory: nothing bounds the error.
  EXPECT_FLOAT_EQ(correlativeWindowFor(std::numeric_limits<double>::infinity(), kWindow, kIcpReach, kSigmas), kWindow);
  // Sigmas 0: the whole window always (the behaviour without the bound).
  EXPECT_FLOAT_EQ(correlativeWindowFor(0.0, kWindow, kIcpReach, 0.0f), kWindow);
}

TEST(ProximityCorrelative, ChainSigmaAddsTranslationVariancesInTheRootFrame) {
  // Translation noise only (yaw almost exact): variances add; a link whose x is uncertain and y
  // exact, after a 90 degree turn, is uncertain along the root's y.
  Graph g;
  const int n = 9;
  for (int i = 1; i <= n; ++i) {
    Link::InfMatrix inf = informationOf(0.1, 1e-6);
    inf(1, 1) = 1e12;
    g.add(Link(i, i + 1, Link::kNeighbor, Transform(1.0, 0.0, 0.0), inf));
  }
  EXPECT_NEAR(sigmaBetween(g, 1, n + 1), 0.1 * std::sqrt(double(n)), 1e-6);
  Graph turned;
  Link::InfMatrix inf = informationOf(0.1, 1e-6);
  inf(1, 1) = 1e12;
  turned.add(Link(1, 2, Link::kNeighbor, Transform(0.0, 0.0, M_PI / 2), informationOf(1e-6, 1e-6)));
  turned.add(Link(2, 3, Link::kNeighbor, Transform(1.0, 0.0, 0.0), inf));
  turned.add(Link(3, 4, Link::kNeighbor, Transform(1.0, 0.0, 0.0), inf));
  EXPECT_NEAR(sigmaBetween(turned, 1, 4), 0.1 * std::sqrt(2.0), 1e-6);
}

TEST(ProximityCorrelative, ChainSigmaGrowsWithHeadingVarianceTimesLeverArmSquared) {
  // Heading noise only, n straight links of length L: the heading error of link k moves the end
  // by its distance to the end, so the variance is q L^2 (1^2 + ... + n^2) (Smith, Self &
  // Cheeseman), not n q L^2.
  Graph g;
  const int n = 10;
  const double L = 0.5, yawSd = 0.01;
  for (int i = 1; i <= n; ++i) g.add(linkOf(i, i + 1, Transform(L, 0.0, 0.0), 1e-6, yawSd));
  double sum = 0.0;
  for (int m = 1; m < n; ++m) sum += double(m) * m;  // the last link's own heading moves nothing after it
  EXPECT_NEAR(sigmaBetween(g, 1, n + 1), yawSd * L * std::sqrt(sum), 1e-4);
  // From the other end, node 1 in node n+1's frame: it also moves with the whole heading error
  // of node n+1, so each link's lever arm is one link longer: q L^2 (1^2 + ... + n^2).
  EXPECT_NEAR(sigmaBetween(g, n + 1, 1), yawSd * L * std::sqrt(sum + double(n) * n), 1e-4);
}

TEST(ProximityCorrelative, ChainSigmaTakesTheLeastUncertainChainAndSkipsVirtualLinks) {
  // 1 -> 2 -> 3 -> 4 strong (3 x 1 m); 4 -> 1 weak but short (a merged-scan proximity link);
  // 4 -> 2 virtual (path planning): it measures nothing.
  Graph g;
  for (int i = 1; i < 4; ++i) g.add(linkOf(i, i + 1, Transform(1.0, 0.0, 0.0), kStrongSd, kStrongYawSd));
  g.add(linkOf(4, 1, Transform(0.2, 0.0, 0.0), kWeakSd, kWeakYawSd, Link::kLocalSpaceClosure));
  g.add(linkOf(4, 2, Transform(0.0, 0.0, 0.0), 1e-6, 1e-6, Link::kVirtualClosure));
  const std::map<int, double> s = graphPositionSigmas(4, 100.0, g.linksOf());
  ASSERT_EQ(s.size(), 4u);
  EXPECT_NEAR(s.at(4), 0.0, 1e-9);
  EXPECT_LT(s.at(1), kWeakSd) << "through the three strong links";
  EXPECT_GT(s.at(1), s.at(2));
  EXPECT_GT(s.at(2), s.at(3));
  EXPECT_GT(s.at(2), kStrongSd * std::sqrt(2.0) - 1e-9) << "not through the virtual link";
  // Within a sigma limit only.
  const std::map<int, double> near = graphPositionSigmas(4, s.at(3) + 1e-6, g.linksOf());
  EXPECT_EQ(near.size(), 2u);
}

}  // namespace
}  // namespace rtabmap

// The correlative search of proximity detection is bounded by how wrong the graph can be
// (RGBD/ProximityCorrelativeDrift). Issue 8: on the Intel log, with the whole 3 m window, a
// robot in one corridor was matched into the parallel corridor on the other side of a wall (the
// other corridor's merged scans see the same doors and walls, shifted by the corridor's width),
// although the graph linked the two places through a few metres of links and knew them apart.
// Each such link was weak enough to pass RGBD/OptimizeMaxError; dozens of them tore the map.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>

#include "../../src/slam/ProximityBySpace.h"
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
    out.emplace_back(c * d.x() + s * d.y() + n(rng), -s * d.x() + c * d.y() + n(rng));
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

constexpr float kWindow = 3.0f;     // RGBD/ProximityCorrelativeWindow of the runs
constexpr float kIcpReach = 0.3f;   // Icp/MaxCorrespondenceDistance of config/lidar2d.ini
constexpr float kDrift = 0.05f;     // RGBD/ProximityCorrelativeDrift default

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

TEST(ProximityCorrelative, WhereTheGraphIsCertainTheSearchCannotReachTheLookAlike) {
  const Eigen::Vector3f robot(8.4f, 1.0f, 0.05f);
  const Points scan = scanFrom(corridorA(), robot, 8.0f, 1);
  // Corridor B's path is 4 m from the robot along the graph (it came through the door a moment
  // ago): the graph cannot be 2 m wrong there.
  const float window = correlativeWindowFor(4.0, kWindow, kIcpReach, kDrift);
  EXPECT_NEAR(window, 0.5f, 1e-5f);
  const CorrelativeResult r = matchCorrelative(corridorB(), scan, robot, proximityOptions(window));
  if (r.found) {
    EXPECT_LT((r.pose.head<2>() - robot.head<2>()).norm(), 0.6f) << "no link into corridor B";
  }
}

TEST(ProximityCorrelative, AfterALongLoopTheWholeWindowStillCorrectsDrift) {
  // Back in corridor A after a 150 m loop: the graph's guess is 1.6 m off along the corridor
  // and 0.4 m across, beyond ICP's reach; the search over the whole window finds the pose.
  const Eigen::Vector3f robot(8.4f, 1.0f, 0.05f);
  const Points scan = scanFrom(corridorA(), robot, 8.0f, 2);
  const Eigen::Vector3f guess = robot + Eigen::Vector3f(1.6f, -0.4f, 0.08f);
  const float window = correlativeWindowFor(150.0, kWindow, kIcpReach, kDrift);
  EXPECT_FLOAT_EQ(window, kWindow);
  const CorrelativeResult r = matchCorrelative(corridorA(), scan, guess, proximityOptions(window));
  ASSERT_TRUE(r.found) << r.why;
  EXPECT_LT((r.pose.head<2>() - robot.head<2>()).norm(), 0.15f);
}

TEST(ProximityCorrelative, WindowGrowsWithTheGraphPathFromIcpReachToTheWholeWindow) {
  EXPECT_FLOAT_EQ(correlativeWindowFor(0.0, kWindow, kIcpReach, kDrift), kIcpReach);
  EXPECT_FLOAT_EQ(correlativeWindowFor(20.0, kWindow, kIcpReach, kDrift), kIcpReach + 1.0f);
  EXPECT_FLOAT_EQ(correlativeWindowFor(1000.0, kWindow, kIcpReach, kDrift), kWindow);
  // Not reachable through the links in memory: nothing bounds the drift.
  EXPECT_FLOAT_EQ(correlativeWindowFor(std::numeric_limits<double>::infinity(), kWindow, kIcpReach, kDrift), kWindow);
  // Drift 0: the whole window always (the behaviour before the bound).
  EXPECT_FLOAT_EQ(correlativeWindowFor(0.0, kWindow, kIcpReach, 0.0f), kWindow);
}

Link linkOf(int from, int to, float metres, Link::Type type = Link::kNeighbor) {
  return Link(from, to, type, Transform(metres, 0, 0, 0, 0, 0), Link::InfMatrix::Identity());
}

TEST(ProximityCorrelative, GraphPathLengthsFollowTheShortestChainOfLinks) {
  // A trajectory 1 -> 5 with 1 m steps; node 5 came back next to 1 (a 0.2 m proximity link);
  // a virtual link of path planning 5 -> 3 measures nothing.
  std::map<int, std::multimap<int, Link>> graph;
  auto add = [&graph](const Link& l) {
    graph[l.from()].emplace(l.to(), l);
    graph[l.to()].emplace(l.from(), l.inverse());
  };
  for (int i = 1; i < 5; ++i) add(linkOf(i, i + 1, 1.0f));
  add(linkOf(5, 1, 0.2f, Link::kLocalSpaceClosure));
  add(linkOf(5, 3, 0.0f, Link::kVirtualClosure));
  auto linksOf = [&graph](int id) -> const std::multimap<int, Link>* {
    const auto it = graph.find(id);
    return it == graph.end() ? nullptr : &it->second;
  };
  const std::map<int, double> all = graphPathLengths(5, 100.0, linksOf);
  ASSERT_EQ(all.size(), 5u);
  EXPECT_NEAR(all.at(5), 0.0, 1e-9);
  EXPECT_NEAR(all.at(1), 0.2, 1e-6);
  EXPECT_NEAR(all.at(2), 1.2, 1e-6);
  EXPECT_NEAR(all.at(4), 1.0, 1e-6);
  EXPECT_NEAR(all.at(3), 2.0, 1e-6) << "through 4, not the virtual link";
  // Within 1.5 m only.
  const std::map<int, double> near = graphPathLengths(5, 1.5, linksOf);
  EXPECT_EQ(near.size(), 4u);
  EXPECT_FALSE(near.count(3));
}

}  // namespace
}  // namespace rtabmap

// Each scenario: its building, its routes (the revisits they promise) and a short simulation.
#include <gtest/gtest.h>

#include <cmath>

#include "SimTestUtil.h"
#include "rtabmap_core/sim/SimDatasetReader.h"

using namespace rtabmap::sim;

namespace {

struct Track {
  std::vector<double> t;
  std::vector<Pose2> pose;
};

// The robot's true trajectory along a route, every 0.5 s.
Track drive(const std::vector<Eigen::Vector2d>& waypoints) {
  const ReferencePath path(waypoints, MotionLimits());
  RobotSimulator robot(path);
  Track track;
  long long steps = 0;
  while (!robot.finished()) {
    const RobotState& s = robot.step();
    if (++steps % 500) continue;
    track.t.push_back(s.t);
    track.pose.push_back(s.pose);
  }
  return track;
}

// Among pairs of poses at the same place (within 0.3 m) visited more than a minute apart, the
// share driven in opposite directions (heading difference over 150 degrees).
double oppositeShare(const Track& track, int* pairs) {
  int same = 0, opposite = 0;
  for (size_t i = 0; i < track.pose.size(); ++i) {
    for (size_t j = i + 1; j < track.pose.size(); ++j) {
      if (track.t[j] - track.t[i] < 60.0) continue;
      if (std::hypot(track.pose[i].x - track.pose[j].x, track.pose[i].y - track.pose[j].y) > 0.3) continue;
      const double d = std::fabs(Pose2::normalizeAngle(track.pose[i].yaw - track.pose[j].yaw));
      if (d > 150.0 * M_PI / 180.0) ++opposite;
      else if (d < 30.0 * M_PI / 180.0) ++same;
    }
  }
  *pairs = same + opposite;
  return *pairs ? static_cast<double>(opposite) / *pairs : 0.0;
}

}  // namespace

TEST(SimScenarios, LoopRevisitsTheSameWayAndReverseTheOtherWay) {
  const Building& b = test::loopBuilding();
  int pairs = 0;
  const Track loop = drive(planRoutes(scenarioSpec("loop"), b, rtabmap::test::drawSeed(7), MotionLimits()).front().waypoints);
  EXPECT_LT(oppositeShare(loop, &pairs), 0.1);
  EXPECT_GT(pairs, 20);
  const Track reverse = drive(planRoutes(scenarioSpec("reverse"), b, rtabmap::test::drawSeed(7), MotionLimits()).front().waypoints);
  EXPECT_GT(oppositeShare(reverse, &pairs), 0.9);
  EXPECT_GT(pairs, 100);  // the whole lap, the other way
}

TEST(SimScenarios, MultisessionRunsStartApartAndOverlapEarlierOnes) {
  const ScenarioSpec spec = scenarioSpec("multisession");
  const Building b = generateBuilding(test::fastSpec(spec.building), 5);
  const auto routes = planRoutes(spec, b, 5, MotionLimits());
  ASSERT_EQ(routes.size(), 3u);
  std::vector<Track> tracks;
  for (const auto& r : routes) tracks.push_back(drive(r.waypoints));
  EXPECT_EQ(routes[0].name, "session1");
  for (size_t k = 1; k < tracks.size(); ++k) {
    // Starts somewhere else than every earlier run started...
    for (size_t e = 0; e < k; ++e) {
      EXPECT_GT(std::hypot(tracks[k].pose[0].x - tracks[e].pose[0].x, tracks[k].pose[0].y - tracks[e].pose[0].y), 3.0);
    }
    // ...and drives over ground an earlier run covered (for at least 5 m worth of poses).
    int shared = 0;
    for (const Pose2& p : tracks[k].pose) {
      bool near = false;
      for (size_t e = 0; e < k && !near; ++e) {
        for (const Pose2& q : tracks[e].pose) {
          if (std::hypot(p.x - q.x, p.y - q.y) < 0.3) {
            near = true;
            break;
          }
        }
      }
      shared += near;
    }
    EXPECT_GT(shared, 20) << "session " << k + 1;
  }
}

TEST(SimScenarios, LongTourLastsTwoHoursAndRevisitsPlaces) {
  const ScenarioSpec spec = scenarioSpec("long");
  EXPECT_EQ(spec.defaultRate, 1.0);
  const Building b = generateBuilding(test::fastSpec(spec.building), 2);
  EXPECT_GE(b.roomCount(), 90);
  const auto routes = planRoutes(spec, b, 2, MotionLimits());
  ASSERT_EQ(routes.size(), 1u);
  const ReferencePath path(routes.front().waypoints, MotionLimits());
  EXPECT_GE(path.duration(), 7200.0);
  EXPECT_LT(path.duration(), 9000.0);
  // Revisits: most navigation nodes on the route are passed several times.
  std::map<int, int> visits;
  for (int n : routes.front().nodes) ++visits[n];
  int often = 0;
  for (const auto& [node, count] : visits) often += count >= 3;
  EXPECT_GT(often, 50);
  // A shorter tour on request.
  const ReferencePath shortPath(planRoutes(spec, b, 2, MotionLimits(), 300.0).front().waypoints, MotionLimits());
  EXPECT_GE(shortPath.duration(), 300.0);
  EXPECT_LT(shortPath.duration(), 600.0);
}

// Every scenario simulates and writes a readable dataset (a short, small version of it).
TEST(SimScenarios, EachScenarioWritesAReadableDataset) {
  for (const std::string& name : scenarioNames()) {
    SCOPED_TRACE(name);
    const ScenarioSpec spec = scenarioSpec(name);
    const Building b = generateBuilding(test::fastSpec(spec.building), 1);
    const auto routes = planRoutes(spec, b, 1, MotionLimits(), name == "long" ? 400.0 : 0.0);
    ASSERT_EQ(static_cast<int>(routes.size()), spec.sessions);
    rtabmap::test::TempDir dir("rtabmap_sim_scenario");
    SimulationConfig config = test::smallConfig(64, 48);
    config.frameRate = 1.0;
    config.maxDuration = 5.0;
    for (size_t k = 0; k < routes.size(); ++k) {
      const std::string sessionDir = routes[k].name.empty() ? dir.path() : dir.path() + "/" + routes[k].name;
      SimDatasetInfo info;
      info.scenario = name;
      info.session = routes[k].name;
      SimDatasetWriter writer(sessionDir, config, info);
      const SessionSummary s = Simulator(*b.world, config).run(ReferencePath(routes[k].waypoints, config.motion), writer, k);
      writer.finish(s);
      SimDatasetReader reader(sessionDir);
      EXPECT_EQ(reader.totalFrames(), 6);
      EXPECT_EQ(reader.meta().session, routes[k].name);
      // Odometry starts at zero in every session; the ground truth where the run starts.
      const SimFrameRecord f = reader.readFrame(0, false, false);
      EXPECT_TRUE(f.odometry.isIdentity(1e-9));
      EXPECT_NEAR(f.groundTruth.x(), routes[k].waypoints.front().x(), 1e-6);
    }
  }
}

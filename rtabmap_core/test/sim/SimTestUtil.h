#pragma once
// Shared fixtures of the simulator tests: small, fast worlds (low-resolution textures), hand-built
// scenes with known geometry, and a cached generated building.
#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

#include "common/TestData.h"
#include "rtabmap_core/sim/Building.h"
#include "rtabmap_core/sim/Materials.h"
#include "rtabmap_core/sim/Scenarios.h"
#include "rtabmap_core/sim/Simulator.h"
#include "rtabmap_core/sim/World.h"

namespace rtabmap::sim::test {

// A building spec that generates in a fraction of a second (64-texel tiles, coarse decals).
inline BuildingSpec fastSpec(BuildingSpec spec = BuildingSpec()) {
  spec.materialSize = 64;
  spec.materialTexelsPerMetre = 16.0f;
  spec.decalTexelsPerMetre = 48.0f;
  return spec;
}

// The loop scenario's building with fast textures (generated once per test binary, by seed):
// seed 7 on the tests' draw, another building on each of `make test-draws`' draws.
inline const Building& loopBuilding(uint64_t seed = rtabmap::test::drawSeed(7)) {
  static std::vector<std::pair<uint64_t, std::unique_ptr<Building>>> cache;
  for (auto& [s, b] : cache) {
    if (s == seed) return *b;
  }
  ScenarioSpec spec = scenarioSpec("loop");
  cache.emplace_back(seed, std::make_unique<Building>(generateBuilding(fastSpec(spec.building), seed)));
  return *cache.back().second;
}

// A box room [0, w] x [0, d] (walls 0.1 thick outside it, ceiling `ceiling`), with the wall at
// x = w textured by `far` and the others by `sides`. Returns the world, finalized unless asked.
inline std::unique_ptr<World> boxRoom(double w, double d, double ceiling, const MaterialSpec& far, const MaterialSpec& sides,
                                      int size = 256, float tpm = 64.0f, bool finalize = true) {
  auto world = std::make_unique<World>(ceiling);
  const int farTex = world->addTexture(makeMaterialTexture(far, size, tpm));
  const int sideTex = world->addTexture(makeMaterialTexture(sides, size, tpm));
  SurfaceMaterial farM, sideM;
  farM.texture = farTex;
  sideM.texture = sideTex;
  const float h = static_cast<float>(ceiling);
  const double t = 0.1;
  auto wall = [&](double x0, double y0, double x1, double y1, const SurfaceMaterial& m) {
    world->addSolid({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, h, SolidKind::kWall, {m}, SurfaceMaterial(), "wall");
  };
  wall(w, -t, w + t, d + t, farM);   // east (far) wall, its inner face at x = w
  wall(-t, -t, 0.0, d + t, sideM);   // west
  wall(-t, -t, w + t, 0.0, sideM);   // south
  wall(-t, d, w + t, d + t, sideM);  // north
  cv::Mat regions = cv::Mat::zeros(1, 1, CV_16UC1);
  SurfaceMaterial floor, ceil;
  floor.texture = sideTex;
  ceil.texture = sideTex;
  world->setRegions(regions, -1000.0, -1000.0, 4000.0, {floor}, {ceil});
  if (finalize) world->finalize();
  return world;
}

inline MaterialSpec material(MaterialKind kind, uint32_t seed, cv::Vec3f colour = {160, 170, 180}) {
  MaterialSpec m;
  m.kind = kind;
  m.seed = seed;
  m.colour = colour;
  m.accent = colour * 0.5f;
  return m;
}

// A simulation config for tests: small images, exact sensors unless changed.
inline SimulationConfig smallConfig(int width = 160, int height = 120) {
  SimulationConfig c;
  c.camera = CameraSpec::standard(width, height);
  c.frameRate = 2.0;
  return c;
}

}  // namespace rtabmap::sim::test

#include "rtabmap_core/sim/SimDatasetWriter.h"

namespace rtabmap::sim::test {

// A sink that keeps every sample and passes it on.
class RecordingSink : public SimulationSink {
 public:
  explicit RecordingSink(SimulationSink* next = nullptr) : next_(next) {}
  void setNext(SimulationSink* next) { next_ = next; }
  void onImu(const ImuSample& s) override {
    imu.push_back(s);
    if (next_) next_->onImu(s);
  }
  void onOdometry(const OdometrySample& s) override {
    odometry.push_back(s);
    if (next_) next_->onOdometry(s);
  }
  void onFrame(SimFrame&& f) override {
    SimFrame copy = f;
    copy.bgr = f.bgr.clone();
    copy.depth = f.depth.clone();
    copy.right = f.right.clone();
    copy.lidar = f.lidar.clone();
    frames.push_back(copy);
    if (next_) next_->onFrame(std::move(f));
  }
  std::vector<ImuSample> imu;
  std::vector<OdometrySample> odometry;
  std::vector<SimFrame> frames;

 private:
  SimulationSink* next_;
};

// A short run of the loop scenario written as a dataset (every sensor on, float depth too),
// with everything the simulator produced kept for comparison. Made once per test binary.
struct RecordedRun {
  std::unique_ptr<rtabmap::test::TempDir> dir;
  SimulationConfig config;
  SessionSummary summary;
  RecordingSink recorded;
};

inline SessionSummary writeRun(const Building& building, const SimulationConfig& config, const std::string& dir, uint64_t seed,
                               RecordingSink* record = nullptr, double seconds = 0.0) {
  const auto routes = planRoutes(scenarioSpec("loop"), building, seed, config.motion);
  const ReferencePath path(routes.front().waypoints, config.motion);
  SimulationConfig c = config;
  if (seconds > 0.0) c.maxDuration = seconds;
  const Simulator simulator(*building.world, c);
  SimDatasetInfo info;
  info.scenario = "loop";
  info.seed = seed;
  info.options = {{"test", "yes"}};
  SimDatasetWriter writer(dir, c, info, 2, true);
  SessionSummary summary;
  if (record) {
    record->setNext(&writer);
    summary = simulator.run(path, *record, seed);
    record->setNext(nullptr);
  } else {
    summary = simulator.run(path, writer, seed);
  }
  writer.finish(summary);
  return summary;
}

inline const RecordedRun& loopRun() {
  static std::unique_ptr<RecordedRun> run;
  if (!run) {
    run = std::make_unique<RecordedRun>();
    run->dir = std::make_unique<rtabmap::test::TempDir>("rtabmap_sim_test");
    run->config = smallConfig(320, 240);
    run->config.lidar3d = true;
    run->summary = writeRun(loopBuilding(), run->config, run->dir->path(), 7, &run->recorded, 20.0);
  }
  return *run;
}

}  // namespace rtabmap::sim::test

// rtabmap-sim: a deterministic robot simulator. Generates an indoor building from a scenario
// and a seed, drives a ground robot through it and writes what its sensors see (RGB-D, stereo,
// 2D lasers, optional 3D lidar, wheel odometry, IMU, exact ground truth) as a "sim" dataset
// folder; with --bag, also a rosbag (through rtabmap-bag).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "common/CommandLine.h"
#include "common/Json.h"
#include "common/ProgressBar.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/sim/Building.h"
#include "rtabmap_core/sim/Random.h"
#include "rtabmap_core/sim/SimDatasetWriter.h"
#include "sim/BagExport.h"
#include "sim/SimOptions.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// Files and folders rtabmap-sim writes (what --overwrite may remove).
const char* kOwnedEntries[] = {"info.yaml",  "calib",      "transforms.txt",      "frames.txt", "groundtruth.txt",
                               "odometry.txt", "odometry_twist.txt", "imu.txt",    "rgb",        "depth",
                               "depth32",    "right",      "scan_urg",            "scan_utm",   "lidar"};

void removeOwned(const fs::path& dir) {
  for (const char* name : kOwnedEntries) fs::remove_all(dir / name);
  for (int k = 1; k <= 16; ++k) {
    const fs::path session = dir / ("session" + std::to_string(k));
    if (fs::exists(session / "info.yaml")) {
      removeOwned(session);
      std::error_code ec;
      fs::remove(session, ec);  // only if now empty
    }
  }
}

void prepareOutput(const std::string& output, bool overwrite) {
  const fs::path dir(output);
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) throw rtabmap::Error(output + " exists and is not a folder");
  if (fs::is_directory(dir, ec) && !fs::is_empty(dir, ec)) {
    if (!overwrite) {
      throw rtabmap::Error(output + " is not empty (use --overwrite to replace a previous rtabmap-sim output there)");
    }
    if (!fs::exists(dir / "info.yaml")) {
      throw rtabmap::Error(output + " is not empty and holds no rtabmap-sim output (info.yaml); not overwriting it");
    }
    removeOwned(dir);
  }
}

}  // namespace

int main(int argc, char** argv) {
  return rtabmap::tools::runTool("rtabmap-sim", [&] {
    namespace sim = rtabmap::sim;
    namespace tsim = rtabmap::tools::sim;
    rtabmap::tools::CommandLine cli(
        "rtabmap-sim",
        "Simulates a ground robot in a procedurally generated indoor building and writes a dataset folder: "
        "RGB-D and stereo images rendered by ray casting, 2D laser scans (URG-04LX, UTM-30LX), optional 16-beam lidar, "
        "wheel odometry with drift, IMU and exact ground truth. Deterministic: the same seed and options give the "
        "same bytes.");
    tsim::declareOptions(cli);
    if (auto exitCode = cli.parse(argc, argv)) return *exitCode;
    tsim::SimRun run = tsim::readOptions(cli);
    const bool quiet = cli.json();

    // Fail early, before minutes of work, when the bag cannot be made; but the folder is still
    // written, as promised.
    const std::string converter = run.bag.empty() ? "" : tsim::findBagConverter(argv[0]);
    prepareOutput(run.output, run.overwrite);

    const auto t0 = Clock::now();
    if (!quiet) std::cerr << "rtabmap-sim: generating the " << run.scenario << " building (seed " << run.seed << ")...\n";
    const sim::Building building = sim::generateBuilding(run.spec.building, run.seed);
    const double generation = std::chrono::duration<double>(Clock::now() - t0).count();
    const std::vector<sim::SessionRoute> routes =
        sim::planRoutes(run.spec, building, run.seed, run.config.motion, run.duration);

    nlohmann::json sessions = nlohmann::json::array();
    int frames = 0;
    double duration = 0.0, distance = 0.0, renderSeconds = 0.0, simulateSeconds = 0.0;
    double stamp = run.config.startStamp;
    std::vector<std::string> sessionNames, sessionDirs;
    for (size_t k = 0; k < routes.size(); ++k) {
      const sim::SessionRoute& route = routes[k];
      const std::string dir = route.name.empty() ? run.output : (fs::path(run.output) / route.name).string();
      sim::SimulationConfig config = run.config;
      config.startStamp = stamp;
      const sim::ReferencePath path(route.waypoints, config.motion);
      const double planned = config.maxDuration > 0.0 ? std::min(config.maxDuration, path.duration()) : path.duration();
      sim::SimDatasetInfo info;
      info.scenario = run.scenario;
      info.session = route.name;
      info.seed = run.seed;
      info.options = run.recorded;
      const sim::Simulator simulator(*building.world, config);
      sim::SimDatasetWriter writer(dir, config, info, run.threads, run.depth32);
      const size_t expected = static_cast<size_t>(std::floor(planned * config.frameRate)) + 1;
      rtabmap::tools::ProgressBar progress(route.name.empty() ? "simulating" : "simulating " + route.name, expected, cli);
      const auto s0 = Clock::now();
      // Sessions get their own noise streams; the session index keeps them apart.
      const uint64_t sessionSeed = sim::hashCombine(run.seed, k);
      const sim::SessionSummary summary =
          simulator.run(path, writer, sessionSeed, [&](double) { progress.increment(); });
      writer.finish(summary);
      progress.finish();
      simulateSeconds += std::chrono::duration<double>(Clock::now() - s0).count();
      frames += summary.frames;
      duration += summary.duration;
      distance += summary.distance;
      renderSeconds += summary.renderSeconds;
      sessions.push_back({{"name", route.name.empty() ? "session" : route.name},
                          {"path", dir},
                          {"groundtruth", (fs::path(dir) / "groundtruth.txt").string()},
                          {"frames", summary.frames},
                          {"duration_s", summary.duration},
                          {"distance_m", summary.distance}});
      sessionNames.push_back(route.name);
      sessionDirs.push_back(dir);
      // The next run starts a minute after this one ends (whole seconds: readable stamps).
      stamp = std::ceil(stamp + summary.duration + 60.0);
    }
    if (routes.size() > 1) {
      sim::SimDatasetInfo info;
      info.scenario = run.scenario;
      info.seed = run.seed;
      info.options = run.recorded;
      sim::writeSimScenarioInfo(run.output, info, sessionNames);
    }

    nlohmann::json bags = nlohmann::json::array();
    if (!run.bag.empty()) {
      if (converter.empty()) {
        throw rtabmap::Error("--bag needs rtabmap-bag (the rosbag converter, built with the ROS package by `make build`), "
                             "which is neither next to rtabmap-sim nor on PATH; the dataset folder " + run.output +
                             " was written: convert it later with `rtabmap-bag --format sim " + run.output + " " + run.bag + "`");
      }
      for (size_t k = 0; k < sessionDirs.size(); ++k) {
        std::string bag = run.bag;
        if (sessionDirs.size() > 1) {
          const fs::path p(run.bag);
          bag = (p.parent_path() / (p.stem().string() + "_" + sessionNames[k] + p.extension().string())).string();
        }
        tsim::runBagConverter(converter, sessionDirs[k], bag, quiet);
        bags.push_back(bag);
      }
    }

    const double renderFps = renderSeconds > 0.0 ? frames / renderSeconds : 0.0;
    const double wallFps = simulateSeconds > 0.0 ? frames / simulateSeconds : 0.0;
    if (cli.json()) {
      rtabmap::tools::printJsonLine({{"scenario", run.scenario},
                                     {"seed", run.seed},
                                     {"frames", frames},
                                     {"duration_s", duration},
                                     {"distance_m", distance},
                                     {"fps", renderFps},
                                     {"write_fps", wallFps},
                                     {"generation_s", generation},
                                     {"rooms", building.roomCount()},
                                     {"output", run.output},
                                     {"sessions", sessions},
                                     {"bags", bags}});
    } else {
      std::cout << "rtabmap-sim: " << run.scenario << " (seed " << run.seed << "): " << frames << " frames, "
                << duration << " s, " << distance << " m driven, in a building of " << building.roomCount() << " rooms\n"
                << "  rendering " << renderFps << " frames/s, with writing " << wallFps << " frames/s (building: "
                << generation << " s)\n";
      for (const auto& s : sessions) std::cout << "  " << s["path"].get<std::string>() << "\n";
      for (const auto& b : bags) std::cout << "  " << b.get<std::string>() << "\n";
    }
    return rtabmap::tools::kExitSuccess;
  });
}

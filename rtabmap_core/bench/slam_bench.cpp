// bench-slam_bench: the SLAM pipeline end to end (the SLAM issue's "How it is shown"), through
// rtabmap-dataset:
//  - 2D lidar + wheel odometry on the Radish logs (no camera: proximity detection closes the
//    loops): ACES relation error of the optimised trajectory (goal: mean translation <= 0.035 m,
//    Cartographer 0.0375) against the raw wheel odometry's; the Intel grid kept as PNG, and the
//    Intel trajectory's deviation from the path of the optimised benchmark graph intel.g2o;
//  - localization on ACES: the second half against a map of the first, local paths against the
//    global scan map (relation error, localizations, update time);
//  - RGB-D on 7-Scenes with F2M odometry: ATE with loop closures vs odometry only;
//  - the simulator's `long` scenario (RGB-D + laser, 1 Hz, memory management) with
//    Rtabmap/TimeThr 500 ms, with Rtabmap/MemoryThr 300, and unbounded: slam_ms_p99 (goal
//    <= 1.2 x the threshold), max WM, loop closures, realtime factor.
// Datasets: ../shared/data (radish, rgbd_7scenes) found beside the repository or given with
// --data; simulated data cached in the work folder (default build/bench_output/slam).
//
// Usage: bench-slam_bench [--work DIR] [--data DIR] [--long-duration S] [--no-long] [--no-rgbd]
//                         [--localization-only]
#include <nlohmann/json.hpp>

#include "RunTool.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

std::string toolsDir;

Json runJson(const std::string& tool, const std::string& arguments) {
  return rtabmap::bench::runToolJson(toolsDir, tool, arguments);
}

// ../shared/data beside an ancestor of the executable.
fs::path findData() {
  for (fs::path p = fs::absolute(toolsDir); !p.empty() && p != p.root_path(); p = p.parent_path()) {
    if (fs::is_directory(p / "shared" / "data")) return p / "shared" / "data";
    if (fs::is_directory(p / ".." / "shared" / "data")) return p / ".." / "shared" / "data";
  }
  return {};
}

// `--config <repository>/config/<name>`: the robots' parameters are declared once, there.
//  - lidar2d.ini, the 2D lidar robot: ICP for everything, 3 DoF, neighbour links refined on
//    scans, proximity on merged scans anywhere in the local map (a loop of the Intel lab is
//    hundreds of links long; every scan offered, nodes every 0.1 m / 0.1 rad);
//  - sim_robot.ini, the simulator's robot: visual links refined by ICP on the laser, 3 DoF, loop
//    closures limited to a 3 m jump (test/slam/SimSlam.cpp reads it too).

std::string repositoryConfig(const std::string& name) {
  for (fs::path p = fs::absolute(toolsDir); !p.empty() && p != p.root_path(); p = p.parent_path()) {
    if (fs::exists(p / "config" / name)) return "--config " + (p / "config" / name).string();
    if (fs::exists(p / "src" / "rtabmap_ros" / "config" / name)) {
      return "--config " + (p / "src" / "rtabmap_ros" / "config" / name).string();
    }
  }
  throw std::runtime_error("config/" + name + " not found above " + toolsDir);
}

void lidar(const fs::path& data, const fs::path& work, Json& result) {
  for (const std::string log : {"intel", "aces"}) {
    const fs::path clf = data / "radish" / (log + ".clf.bz2");
    if (!fs::exists(clf)) {
      std::cout << log << ": skipped (" << clf << " absent)" << std::endl;
      continue;
    }
    const fs::path out = work / log;
    const Json s = runJson("rtabmap-dataset", "--format carmen --odom wheel --slam --output " + out.string() + " " +
                                                  repositoryConfig("lidar2d.ini") + " " + clf.string());
    std::cout << log << ": " << s["frames"] << " scans, " << s["nodes"] << " nodes, " << s["proximity_links"]
              << " proximity links, " << s["rejected_links"] << " rejected; update median " << s["slam_ms_median"]
              << " ms, p99 " << s["slam_ms_p99"] << " ms, max " << s["slam_ms_max"] << " ms; realtime x"
              << s["realtime_factor"] << "; grid " << (out / "grid.png").string() << std::endl;
    Json entry = {{"slam", s}};
    const fs::path relations = data / "radish" / (log + ".relations");
    if (fs::exists(relations)) {
      const Json slam = runJson("rtabmap-eval", "relations --relations " + relations.string() + " --est " +
                                                    (out / "frames.tum").string());
      const Json odom = runJson("rtabmap-eval", "relations --relations " + relations.string() + " --est " +
                                                    (out / "odom.tum").string());
      const double t = slam["translation"]["mean"], r = slam["rotation_deg"]["mean"];
      std::cout << "  " << log << " relations (" << slam["used"] << " used): SLAM " << t << " m / " << r
                << " deg, wheel odometry " << odom["translation"]["mean"] << " m / " << odom["rotation_deg"]["mean"]
                << " deg; goal mean translation <= 0.035 m (Cartographer 0.0375): " << (t <= 0.035 ? "met" : "NOT met")
                << std::endl;
      // Local relations (scans at most 5 s apart) are what the neighbour links decide, loop ones
      // what loop closure decides: the mean above mixes both.
      std::cout << "    local (" << slam["local"]["translation"]["count"] << "): SLAM "
                << slam["local"]["translation"]["mean"] << " m, wheel odometry " << odom["local"]["translation"]["mean"]
                << " m; loop (" << slam["loop"]["translation"]["count"] << "): SLAM "
                << slam["loop"]["translation"]["mean"] << " m, wheel odometry " << odom["loop"]["translation"]["mean"]
                << " m" << std::endl;
      // What the reference resolves: its own triangles' inconsistency (RelationError.h).
      if (slam["reference"]["triangles"].get<long>() > 0) {
        std::cout << "    reference: " << slam["reference"]["triangles"] << " triangles of relations disagree by "
                  << slam["reference"]["translation"]["mean"] << " m on average, a relation's own error ~"
                  << slam["reference"]["relation_rms"] << " m RMS" << std::endl;
      }
      entry["relations_slam"] = slam;
      entry["relations_odom"] = odom;
    }
    // No relations for Intel, but a benchmark pose graph of the same run (posegraphs/intel.g2o,
    // built by others from the same log): at its optimum, its path against ours shows whether
    // the map's shape (its bowed inner corridors, say) is shared or ours alone.
    const fs::path graph = data / "posegraphs" / (log + ".g2o");
    if (fs::exists(graph)) {
      const fs::path optimum = out / (log + "_reference.g2o");
      const Json g = runJson("rtabmap-g2o", "--iterations 100 " + graph.string() + " " + optimum.string());
      const auto deviation = [&](const std::string& est) {
        return runJson("rtabmap-eval", "path --ref " + optimum.string() + " --est " + (out / est).string());
      };
      const Json slam = deviation("frames.tum"), odom = deviation("odom.tum");
      std::cout << "  " << log << " path deviation from " << graph.filename().string() << "'s optimum (chi2 "
                << g["final_chi2"] << ", " << slam["reference_length"] << " m): SLAM median "
                << slam["deviation"]["median"] << " m, p90 " << slam["p90"] << ", p99 " << slam["p99"] << ", max "
                << slam["deviation"]["max"] << "; wheel odometry median " << odom["deviation"]["median"] << " m"
                << std::endl;
      entry["path_slam"] = slam;
      entry["path_odom"] = odom;
    }
    result[log] = entry;
  }
}

// Localization on real data: ACES's first half mapped (--max-frames), its second half localised
// against that map (the robot starts where mapping ended; a good part of the second half drives
// corridors the first never saw), by proximity detection on local paths and on the global scan
// map (RGBD/ProximityGlobalScanMap): localizations, update time and the relation error of every
// frame's pose in the map (DIR/localization.tum) against the relations of the second half.
void acesLocalization(const fs::path& data, const fs::path& work, Json& result) {
  const fs::path clf = data / "radish" / "aces.clf.bz2", relations = data / "radish" / "aces.relations";
  if (!fs::exists(clf) || !fs::exists(relations)) return;
  constexpr int kHalf = 3687;  // of 7,374 scans
  const fs::path map = work / "aces_half";
  const std::string robot = "--format carmen --odom wheel " + repositoryConfig("lidar2d.ini") + " ";
  const Json m = runJson("rtabmap-dataset", robot + "--slam --max-frames " + std::to_string(kHalf) + " --output " +
                                                map.string() + " " + clf.string());
  std::cout << "aces localization: first " << kHalf << " scans mapped (" << m["nodes"] << " nodes)" << std::endl;
  Json entry = {{"map", m}};
  for (const bool global : {false, true}) {
    const std::string name = global ? "global_scan_map" : "local_paths";
    const fs::path dir = work / ("aces_localization_" + name);
    fs::create_directories(dir);
    fs::copy_file(map / "rtabmap.db", dir / "rtabmap.db", fs::copy_options::overwrite_existing);
    const Json l = runJson("rtabmap-dataset", robot + "--localization --start " + std::to_string(kHalf) +
                                                  " --RGBD/ProximityGlobalScanMap " + (global ? "true" : "false") +
                                                  " --output " + dir.string() + " " + clf.string());
    const Json r = runJson("rtabmap-eval", "relations --relations " + relations.string() + " --est " +
                                               (dir / "localization.tum").string());
    std::cout << "  " << name << ": " << l["localizations"] << " localizations over " << l["frames"]
              << " scans, update median " << l["slam_ms_median"] << " ms, p99 " << l["slam_ms_p99"]
              << " ms; relations (" << r["used"] << "): " << r["translation"]["mean"] << " m / "
              << r["rotation_deg"]["mean"] << " deg, local " << r["local"]["translation"]["mean"] << " m, loop "
              << r["loop"]["translation"]["mean"] << " m" << std::endl;
    entry[name] = {{"run", l}, {"relations", r}};
  }
  result["aces_localization"] = entry;
}

void rgbd(const fs::path& data, const fs::path& work, Json& result) {
  const fs::path scenes = data / "rgbd_7scenes";
  if (!fs::exists(scenes)) {
    std::cout << "7-Scenes: skipped (" << scenes << " absent)" << std::endl;
    return;
  }
  const Json s = runJson("rtabmap-dataset", "--format 7scenes --odom f2m --slam --output " + (work / "7scenes").string() +
                                                " --Rtabmap/DetectionRate 2 --RGBD/CreateOccupancyGrid false " +
                                                scenes.string());
  std::cout << "7-Scenes RGB-D (F2M): " << s["frames"] << " frames, " << s["nodes"] << " nodes, " << s["loop_closures"]
            << " loop closures, " << s["proximity_links"] << " proximity links; ATE odometry " << s["odom_ate_rmse"]
            << " m, SLAM " << s["ate_rmse"] << " m (goal: SLAM <= odometry: "
            << (s["ate_rmse"].get<double>() <= s["odom_ate_rmse"].get<double>() ? "met" : "NOT met") << ")" << std::endl;
  result["7scenes"] = s;
}

void longRun(const fs::path& work, const std::string& duration, Json& result) {
  const fs::path sim = work / "sim_long";
  if (!fs::exists(sim / "info.yaml")) {
    std::cout << "simulating long into " << sim << " ..." << std::endl;
    runJson("rtabmap-sim", "--scenario long --rate 1 --width 320 --height 240 --no-stereo --no-urg --overwrite " +
                               (duration.empty() ? std::string() : "--duration " + duration) + " --output " + sim.string());
  }
  struct Budget {
    const char* name;
    std::string params;
    double limitMs;
  };
  for (const Budget& b : {Budget{"time_thr_500", "--Rtabmap/TimeThr 500", 500.0},
                          Budget{"memory_thr_300", "--Rtabmap/MemoryThr 300", 0.0},
                          Budget{"unbounded", "", 0.0}}) {
    const Json s = runJson("rtabmap-dataset", "--format sim --odom wheel --slam --output " +
                                                  (work / (std::string("long_") + b.name)).string() + " " +
                                                  repositoryConfig("sim_robot.ini") +
                                                  " " + b.params + " " + sim.string());
    std::cout << "long, " << b.name << ": " << s["frames"] << " frames, " << s["nodes"] << " nodes; update median "
              << s["slam_ms_median"] << " ms, p99 " << s["slam_ms_p99"] << " ms, max " << s["slam_ms_max"]
              << " ms; max WM " << s["max_wm_size"] << "; loop closures " << s["loop_closures"] << ", proximity "
              << s["proximity_links"] << "; transferred " << s["transferred"] << ", retrieved " << s["retrieved"]
              << "; realtime x" << s["realtime_factor"] << "; ATE " << s.value("ate_rmse", -1.0) << " m";
    if (b.limitMs > 0) std::cout << " (goal p99 <= " << 1.2 * b.limitMs << " ms: " << (s["slam_ms_p99"].get<double>() <= 1.2 * b.limitMs ? "met" : "NOT met") << ")";
    std::cout << std::endl;
    result[std::string("long_") + b.name] = s;
  }
}

}  // namespace

int main(int argc, char** argv) {
  toolsDir = fs::path(argv[0]).parent_path().string();
  fs::path work = fs::path(toolsDir) / ".." / "bench_output" / "slam";
  fs::path data;
  std::string longDuration;
  bool runLong = true, runRgbd = true, localizationOnly = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--work") && i + 1 < argc) work = argv[++i];
    else if (!std::strcmp(argv[i], "--data") && i + 1 < argc) data = argv[++i];
    else if (!std::strcmp(argv[i], "--long-duration") && i + 1 < argc) longDuration = argv[++i];
    else if (!std::strcmp(argv[i], "--no-long")) runLong = false;
    else if (!std::strcmp(argv[i], "--no-rgbd")) runRgbd = false;
    else if (!std::strcmp(argv[i], "--localization-only")) localizationOnly = true;
  }
  if (data.empty()) data = findData();
  fs::create_directories(work);
  Json result = {{"bench", "slam"}};
  try {
    if (data.empty()) {
      std::cout << "../shared/data not found: the Radish and 7-Scenes parts are skipped (--data DIR)" << std::endl;
    } else {
      if (!localizationOnly) lidar(data, work, result);
      acesLocalization(data, work, result);
      if (runRgbd && !localizationOnly) rgbd(data, work, result);
    }
    if (runLong && !localizationOnly) longRun(work, longDuration, result);
  } catch (const std::exception& e) {
    std::cerr << "bench-slam_bench: " << e.what() << std::endl;
    return 1;
  }
  std::cout << result.dump() << std::endl;
  return 0;
}

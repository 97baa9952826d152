// bench-maps_bench: how fast are the maps for navigation, and do they look right?
//
// Laser logs (../shared/data/radish: Intel lab, ACES), with the poses of the SLAM pipeline: the
// log is mapped first by rtabmap-dataset --slam with config/lidar2d.ini (wheel odometry, ICP
// neighbour refinement, proximity loop closures), each scan then taking its frames.tum pose (its
// last node's optimised pose composed with the odometry since). --odometry-poses uses the lidar
// scan-to-map odometry instead (Odometry::create with Reg/Strategy 1, Odom/Strategy 0, the wheel
// odometry as motion guess; the raw wheel odometry when that fails or is not in the library), as
// when rtabmap-dataset is not built. Nodes are taken as RTAB-Map does with RGBD/LinearUpdate and
// AngularUpdate thresholds (chosen to give about 1,000 nodes on Intel):
//  - local grid time per scan (2D ray tracing), bytes per node;
//  - incremental global 2D update per node;
//  - re-assembly after a loop closure (every node moved) and after a small correction (the last
//    tenth moved): the full and region paths both measured, and the path the grid chooses;
//  - the grid as PNG, PGM + YAML in the output folder, with its wall thickness.
// 7-Scenes RGB-D frames (../shared/data/rgbd_7scenes), with their KinectFusion poses:
//  - local grid time per frame, 2D (projection + 2D ray tracing) and 3D (with and without 3D ray
//    tracing), bytes per node;
//  - incremental 2D update, OctoMap insertion rate with ray tracing (points per second, wall and
//    process CPU time, median of 3 builds), OctoMap rebuild after a loop closure; PNG previews of
//    the 2D grid and the OctoMap projection.
// Human-readable lines first, then one JSON line with every figure.
//
// Usage: bench-maps_bench [--out DIR] [--data DIR] [--max-scans N] [--only intel|aces|7scenes]
//                         [--odometry-poses [--wheel-odometry]] [--slam-dir DIR]
//   --slam-dir DIR: take DIR/<log>/frames.tum of an earlier rtabmap-dataset --slam run instead
//   of mapping the log again (default: map it into OUT/slam/<log>).
#include <time.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "RunTool.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/eval/Trajectory.h"
#include "rtabmap_core/maps/LocalGridMaker.h"
#include "rtabmap_core/maps/MapIO.h"
#include "rtabmap_core/maps/OccupancyGrid.h"
#include "rtabmap_core/maps/OctoMap.h"
#include "rtabmap_core/odometry/Odometry.h"

namespace fs = std::filesystem;
using namespace rtabmap;
using Clock = std::chrono::steady_clock;
using Json = nlohmann::json;
using Path = GridUpdateSummary::Path;

namespace {

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// CPU time of this thread (ms). The machines running make bench are shared: wall times include
// the time other processes held the core, CPU times do not. Both are printed.
double cpuMs() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

// CPU time of the whole process (ms), for work that may use more than one thread.
double processCpuMs() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

struct Settings {
  std::string out;
  std::string data;
  int maxScans = 0;
  bool wheelOdometry = false;
  bool odometryPoses = false;  // scan-matched (or wheel) odometry poses instead of SLAM's
  std::string slamDir;         // an earlier SLAM run: slamDir/<log>/frames.tum
  std::string only;            // intel, aces or 7scenes: that part alone
  std::string argv0;
};

// Summary of a series of times (ms).
struct Series {
  std::vector<double> v;
  void add(double x) { v.push_back(x); }
  double mean() const { return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / v.size(); }
  double pct(double p) const {
    if (v.empty()) return 0.0;
    std::vector<double> s = v;
    std::sort(s.begin(), s.end());
    return s[std::min(s.size() - 1, static_cast<size_t>(p * (s.size() - 1) + 0.5))];
  }
  double median() const { return pct(0.5); }
  double max() const { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }
  Json json() const { return {{"mean", mean()}, {"median", median()}, {"p95", pct(0.95)}, {"max", max()}, {"n", v.size()}}; }
};

// ../shared/data, looked for beside every ancestor of the working folder and of the executable
// (make bench runs from the repository root; the executable lives under build/).
std::string findUp(const std::vector<fs::path>& starts, const std::function<bool(const fs::path&)>& match) {
  for (fs::path p : starts) {
    for (; !p.empty(); p = p.parent_path()) {
      if (match(p)) return p.string();
      if (p == p.root_path()) break;
    }
  }
  return "";
}

std::vector<fs::path> startFolders() {
  std::vector<fs::path> starts{fs::current_path()};
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) starts.push_back(exe.parent_path());
  return starts;
}

std::string dataDir(const Settings& s) {
  if (!s.data.empty()) return s.data;
  if (const char* env = std::getenv("RTABMAP_DATA_DIR")) return env;
  const std::string found = findUp(startFolders(), [](const fs::path& p) { return fs::is_directory(p / "shared" / "data"); });
  return found.empty() ? "" : (fs::path(found) / "shared" / "data").string();
}

std::string outputDir(const Settings& s) {
  if (!s.out.empty()) return s.out;
  // The repository: the folder holding rtabmap_core/ and the Makefile.
  const std::string repo = findUp(startFolders(), [](const fs::path& p) {
    return fs::is_directory(p / "rtabmap_core") && fs::exists(p / "Makefile");
  });
  return ((repo.empty() ? fs::current_path() : fs::path(repo) / "build") / "bench_output" / "maps").string();
}

// Thickness of walls in a grid: for each occupied cell, the shorter of its horizontal and vertical
// runs of occupied cells. Clean walls are 1-2 cells; doubled or smeared walls are thicker.
Json wallThickness(const GridMap& m) {
  std::vector<int> hist(5, 0);  // 1, 2, 3, 4, 5+
  int total = 0;
  for (int r = 0; r < m.height(); ++r) {
    for (int c = 0; c < m.width(); ++c) {
      if (m.data.at<int8_t>(r, c) != GridMap::kOccupied) continue;
      auto run = [&](int dr, int dc) {
        int n = 1;
        for (int k = 1; r + k * dr >= 0 && r + k * dr < m.height() && c + k * dc >= 0 && c + k * dc < m.width() &&
                        m.data.at<int8_t>(r + k * dr, c + k * dc) == GridMap::kOccupied; ++k) ++n;
        for (int k = 1; r - k * dr >= 0 && r - k * dr < m.height() && c - k * dc >= 0 && c - k * dc < m.width() &&
                        m.data.at<int8_t>(r - k * dr, c - k * dc) == GridMap::kOccupied; ++k) ++n;
        return n;
      };
      const int t = std::min(run(0, 1), run(1, 0));
      ++hist[std::min(t, 5) - 1];
      ++total;
    }
  }
  const double within2 = total ? double(hist[0] + hist[1]) / total : 0.0;
  return {{"occupied_cells", total}, {"thickness_1", hist[0]}, {"thickness_2", hist[1]}, {"thickness_3", hist[2]},
          {"thickness_4", hist[3]}, {"thickness_5plus", hist[4]}, {"fraction_within_2_cells", within2}};
}

void saveGrid(const GridMap& m, const std::string& dir, const std::string& name, Json& j) {
  fs::create_directories(dir);
  const std::string png = (fs::path(dir) / (name + ".png")).string();
  writeGridPng(m, png, 2);
  writeMapServer(m, (fs::path(dir) / (name + ".pgm")).string(), (fs::path(dir) / (name + ".yaml")).string());
  j["png"] = png;
  j["width"] = m.width();
  j["height"] = m.height();
  j["occupied"] = m.countOccupied();
  j["free"] = m.countFree();
}

// ------------------------------------------------------------------------------ laser logs

struct Frame {
  SensorData data;
  Transform pose;  // SLAM-optimised, lidar odometry or wheel odometry
};

struct LaserLog {
  std::vector<Frame> frames;
  std::string poseSource;
  Series odometryMs;
  int lost = 0;
};

// Poses of the scans of a log: scan-matched when the lidar odometry is available, else the wheel
// odometry. Returns the pose of each scan, in order.
class ScanPoses {
 public:
  explicit ScanPoses(bool wheelOnly, std::string* source) {
    if (!wheelOnly) {
      try {
        odometry_ = Odometry::create({{"Reg/Strategy", "1"}, {"Odom/Strategy", "0"}, {"Reg/Force3DoF", "true"}});
        *source = "lidar scan-to-map odometry (" + Odometry::typeName(odometry_->type()) + ") with wheel guess";
        return;
      } catch (const std::exception& e) {
        std::cout << "  lidar odometry unavailable (" << e.what() << "): wheel odometry poses\n";
      }
    }
    *source = "wheel odometry";
  }

  // Pose of the next scan; *lost when the scan matcher failed (the wheel motion is used).
  Transform next(SensorData& data, double* ms, bool* lost) {
    const Transform wheel = data.odomPose();
    const Transform previousWheel = previousWheel_;
    previousWheel_ = wheel;
    *ms = -1.0;
    *lost = false;
    if (odometry_) {
      const Transform guess = previousWheel.isNull() || wheel.isNull() ? Transform() : previousWheel.inverse() * wheel;
      OdometryInfo info;
      const Clock::time_point t = Clock::now();
      const Transform p = odometry_->process(data, guess, &info);
      *ms = msSince(t);
      *lost = p.isNull();
      pose_ = p.isNull() ? (guess.isNull() ? pose_ : pose_ * guess) : p;
      return pose_;
    }
    if (!wheel.isNull()) pose_ = wheel;
    return pose_;
  }

 private:
  std::unique_ptr<Odometry> odometry_;
  Transform previousWheel_;
  Transform pose_ = Transform::Identity();
};

// The folder of the command-line tools: beside this executable (build/bin, or the folder the
// build put it in), as argv[0] or /proc/self/exe says.
std::string toolsDir(const Settings& s) {
  std::vector<fs::path> dirs{fs::path(s.argv0).parent_path()};
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back(exe.parent_path());
  for (const fs::path& d : dirs) {
    if (fs::exists(d / "rtabmap-dataset")) return fs::absolute(d).string();
  }
  return "";
}

// config/lidar2d.ini of the repository (or of the catkin workspace's source folder).
std::string lidar2dConfig(const std::string& tools) {
  std::vector<fs::path> starts = startFolders();
  if (!tools.empty()) starts.push_back(tools);
  const std::string found = findUp(starts, [](const fs::path& p) {
    return fs::exists(p / "config" / "lidar2d.ini") || fs::exists(p / "src" / "rtabmap_ros" / "config" / "lidar2d.ini");
  });
  if (found.empty()) return "";
  const fs::path direct = fs::path(found) / "config" / "lidar2d.ini";
  return (fs::exists(direct) ? direct : fs::path(found) / "src" / "rtabmap_ros" / "config" / "lidar2d.ini").string();
}

// The optimised pose of every scan of a log, from the SLAM pipeline: rtabmap-dataset --slam with
// the 2D lidar configuration (or an earlier run's frames.tum with --slam-dir). Empty, with the
// reason in `source`, when the tool or the configuration is missing or the run fails.
struct SlamPoses {
  Trajectory frames;
  std::string source;
  Json summary;
  double seconds = 0.0;
};

SlamPoses slamPoses(const std::string& name, const std::string& clf, const Settings& s, const std::string& out) {
  SlamPoses r;
  fs::path dir;
  try {
    if (!s.slamDir.empty()) {
      dir = fs::path(s.slamDir) / name;
      r.source = "SLAM poses (optimised, every scan) read from " + (dir / "frames.tum").string();
    } else {
      const std::string tools = toolsDir(s), config = lidar2dConfig(tools);
      if (tools.empty() || config.empty()) {
        r.source = tools.empty() ? "rtabmap-dataset not found beside the bench" : "config/lidar2d.ini not found";
        return r;
      }
      dir = fs::path(out) / "slam" / name;
      std::string args = "--format carmen --odom wheel --slam --output " + dir.string() + " --config " + config;
      if (s.maxScans > 0) args += " --max-frames " + std::to_string(s.maxScans);
      const Clock::time_point t0 = Clock::now();
      r.summary = bench::runToolJson(tools, "rtabmap-dataset", args + " " + clf);
      r.seconds = msSince(t0) / 1000.0;
      r.source = "SLAM poses (rtabmap-dataset --slam, " + fs::path(config).filename().string() + ", " +
                 std::to_string(r.summary.value("nodes", 0)) + " SLAM nodes, " +
                 std::to_string(r.summary.value("proximity_links", 0)) + " proximity links, mapped in " +
                 std::to_string(static_cast<int>(r.seconds)) + " s)";
    }
    r.frames = readTrajectory((dir / "frames.tum").string(), TrajectoryFormat::kTum);
    r.frames.sortByStamp();
  } catch (const std::exception& e) {
    r.frames = Trajectory();
    r.source = std::string("SLAM run failed: ") + e.what();
  }
  return r;
}

// The scans of a log with their poses: the SLAM trajectory's (scans it has no pose for are left
// out) when `slam` is not empty, else the scan-matched odometry's.
LaserLog readLaserLog(const std::string& path, const Settings& s, const Trajectory& slam) {
  LaserLog log;
  DatasetReaderOptions ro;
  ro.images = false;
  ro.odometry = false;
  ro.imu = false;
  ro.maxFrames = s.maxScans;
  std::unique_ptr<DatasetReader> reader = openDatasetReader("carmen", path, ro);
  std::unique_ptr<ScanPoses> poses;
  if (slam.empty()) poses = std::make_unique<ScanPoses>(s.wheelOdometry, &log.poseSource);
  DatasetRecord rec;
  while (reader->next(rec)) {
    if (rec.kind != DatasetRecord::Kind::kFrame || rec.data.laserScanRaw().empty()) continue;
    if (!poses) {
      const long i = slam.nearest(rec.data.stamp(), 1e-4);
      if (i < 0 || slam[static_cast<size_t>(i)].pose.isNull()) {
        ++log.lost;
        continue;
      }
      log.frames.push_back({rec.data, slam[static_cast<size_t>(i)].pose});
      continue;
    }
    SensorData d = rec.data;
    double ms = 0.0;
    bool lost = false;
    const Transform pose = poses->next(d, &ms, &lost);
    if (ms >= 0.0) log.odometryMs.add(ms);
    if (lost) ++log.lost;
    log.frames.push_back({rec.data, pose});
  }
  return log;
}

// Nodes as RTAB-Map makes them: a frame becomes a node when the robot moved more than `linear`
// or turned more than `angular` since the last node.
std::vector<size_t> selectNodes(const std::vector<Frame>& frames, double linear, double angular) {
  std::vector<size_t> nodes;
  for (size_t i = 0; i < frames.size(); ++i) {
    if (nodes.empty()) {
      nodes.push_back(i);
      continue;
    }
    const Transform d = frames[nodes.back()].pose.inverse() * frames[i].pose;
    if (d.getNorm() > linear || d.getAngle() > angular) nodes.push_back(i);
  }
  return nodes;
}

// A loop-closure correction: the error found at the end of the loop spread along the graph, as
// an optimiser does (node i of n moves by fraction f = i / n of it).
std::map<int, Transform> corrected(const std::map<int, Transform>& poses, size_t firstMoved) {
  std::map<int, Transform> out;
  size_t i = 0;
  const double n = static_cast<double>(poses.size());
  for (const auto& [id, p] : poses) {
    const double f = i < firstMoved ? 0.0 : (static_cast<double>(i) + 1.0) / n;
    out[id] = i < firstMoved ? p : Transform(0.25 * f, -0.15 * f, 0.02 * f) * p;
    ++i;
  }
  return out;
}

// Re-assembly timings: each path forced, then the grid's own choice, alternating between the
// two graphs so that every update really moves the nodes.
Json reassembly(OccupancyGrid& grid, const std::map<int, Transform>& a, const std::map<int, Transform>& b,
                const char* label) {
  Series full, region, chosen, fullCpu, regionCpu, chosenCpu;
  std::map<std::string, int> choices;
  const std::map<int, Transform>* graphs[2] = {&b, &a};
  int k = 0;
  for (int rep = 0; rep < 5; ++rep) {
    for (Path forced : {Path::kFull, Path::kRegion, Path::kNone}) {
      grid.forceNextPath(forced);
      const double c0 = cpuMs();
      const GridUpdateSummary s = grid.update(*graphs[k++ % 2]);
      const double cpu = cpuMs() - c0;
      (forced == Path::kFull ? full : forced == Path::kRegion ? region : chosen).add(s.timeMs);
      (forced == Path::kFull ? fullCpu : forced == Path::kRegion ? regionCpu : chosenCpu).add(cpu);
      if (forced == Path::kNone) ++choices[pathName(s.path)];
    }
  }
  std::printf("  %-32s full %6.1f ms (cpu %6.1f)  region %6.1f ms (cpu %6.1f)  chosen %6.1f ms (cpu %6.1f;", label,
              full.median(), fullCpu.median(), region.median(), regionCpu.median(), chosen.median(), chosenCpu.median());
  for (const auto& [name, n] : choices) std::printf(" %s x%d", name.c_str(), n);
  std::printf(")\n");
  return {{"full_ms", full.json()}, {"region_ms", region.json()}, {"chosen_ms", chosen.json()},
          {"full_cpu_ms", fullCpu.json()}, {"region_cpu_ms", regionCpu.json()}, {"chosen_cpu_ms", chosenCpu.json()},
          {"choices", choices}};
}

Json benchLaser(const std::string& name, const std::string& path, const Settings& s, const std::string& out,
                size_t targetNodes) {
  Json j;
  std::printf("%s (%s)\n", name.c_str(), path.c_str());
  SlamPoses slam;
  if (!s.odometryPoses) {
    std::printf("  mapping with the SLAM pipeline for its poses...\n");
    std::fflush(stdout);
    slam = slamPoses(name, path, s, out);
    if (slam.frames.empty()) std::printf("  no SLAM poses (%s): odometry poses\n", slam.source.c_str());
    if (!slam.summary.is_null()) j["slam"] = slam.summary;
    j["slam_seconds"] = slam.seconds;
  }
  const Clock::time_point t0 = Clock::now();
  LaserLog log = readLaserLog(path, s, slam.frames);
  if (!slam.frames.empty()) log.poseSource = slam.source;
  std::printf("  %zu scans read in %.1f s; poses: %s", log.frames.size(), msSince(t0) / 1000.0, log.poseSource.c_str());
  if (!log.odometryMs.v.empty()) std::printf(" (%.1f ms/scan, %d lost)", log.odometryMs.mean(), log.lost);
  else if (log.lost > 0) std::printf(" (%d scans without a pose left out)", log.lost);
  std::printf("\n");
  j["scans"] = log.frames.size();
  j["pose_source"] = log.poseSource;
  j["odometry_ms_per_scan"] = log.odometryMs.mean();
  j["odometry_lost"] = log.lost;
  if (log.frames.empty()) return j;

  // Update thresholds giving about targetNodes nodes (RGBD/LinearUpdate = AngularUpdate in rad):
  // the node count falls as the threshold grows, so bisect for the smallest threshold giving at
  // most targetNodes.
  double below = 0.01, above = 2.0;
  for (int it = 0; it < 20; ++it) {
    const double mid = 0.5 * (below + above);
    (selectNodes(log.frames, mid, mid).size() > targetNodes ? below : above) = mid;
  }
  const double threshold = above;
  const std::vector<size_t> nodes = selectNodes(log.frames, threshold, threshold);
  std::printf("  %zu nodes (RGBD/LinearUpdate %.2f m, RGBD/AngularUpdate %.2f rad)\n", nodes.size(), threshold, threshold);
  j["nodes"] = nodes.size();
  j["update_threshold"] = threshold;

  LocalGridOptions lo = LocalGridOptions::fromParameters(
      {{"Grid/Sensor", "0"}, {"Grid/CellSize", "0.05"}, {"Grid/RangeMax", "0"}});
  Series localMs, localCpu;
  Series raw, compressed;
  std::map<int, LocalGrid> grids;
  std::map<int, Transform> poses;
  int failed = 0;
  for (size_t k = 0; k < nodes.size(); ++k) {
    const Frame& f = log.frames[nodes[k]];
    const Clock::time_point t = Clock::now();
    const double c0 = cpuMs();
    const LocalGridResult r = createLocalGrid(f.data, lo);
    localCpu.add(cpuMs() - c0);
    localMs.add(msSince(t));
    if (!r.success) {
      ++failed;
      continue;
    }
    const LocalGridBytes b = localGridBytes(r.grid);
    raw.add(b.raw);
    compressed.add(b.compressed);
    grids[static_cast<int>(k) + 1] = r.grid;
    poses[static_cast<int>(k) + 1] = f.pose;
  }
  std::printf("  local grid per scan: %.2f ms mean, %.2f ms p95, cpu %.2f ms mean (%d failed); %.0f B/node raw, %.0f B/node compressed\n",
              localMs.mean(), localMs.pct(0.95), localCpu.mean(), failed, raw.mean(), compressed.mean());
  j["local_grid_ms"] = localMs.json();
  j["local_grid_cpu_ms"] = localCpu.json();
  j["bytes_per_node_2d"] = {{"raw", raw.mean()}, {"compressed", compressed.mean()}};

  GlobalGridOptions go = GlobalGridOptions::fromParameters({{"Grid/CellSize", "0.05"}});
  OccupancyGrid grid(go);
  Series incremental, incrementalCpu;
  std::map<int, Transform> graph;
  for (const auto& [id, g] : grids) {
    const Clock::time_point t = Clock::now();
    const double c0 = cpuMs();
    grid.addLocalGrid(id, g);
    graph[id] = poses.at(id);
    grid.update(graph);
    incrementalCpu.add(cpuMs() - c0);
    incremental.add(msSince(t));
  }
  std::printf("  incremental global update per node: %.3f ms mean, %.3f ms p95, %.3f ms max (cpu %.3f mean, %.3f p95)\n",
              incremental.mean(), incremental.pct(0.95), incremental.max(), incrementalCpu.mean(), incrementalCpu.pct(0.95));
  j["incremental_update_ms"] = incremental.json();
  j["incremental_update_cpu_ms"] = incrementalCpu.json();
  const Clock::time_point tm = Clock::now();
  const GridMap m = grid.map();
  const double mapMs = msSince(tm);
  Json picture;
  saveGrid(m, out, name, picture);
  picture["map_ms"] = mapMs;
  picture["walls"] = wallThickness(m);
  j["grid"] = picture;
  std::printf("  map %dx%d (%.1f ms to publish), walls within 2 cells: %.1f %%; %s\n", m.width(), m.height(), mapMs,
              100.0 * picture["walls"]["fraction_within_2_cells"].get<double>(), picture["png"].get<std::string>().c_str());
  j["loop_closure_all_moved"] = reassembly(grid, poses, corrected(poses, 0), "re-assembly, every node moved:");
  j["loop_closure_last_tenth_moved"] =
      reassembly(grid, poses, corrected(poses, poses.size() * 9 / 10), "re-assembly, last tenth moved:");
  grid.update(poses);
  j["memory_bytes"] = grid.memoryUsed();
  return j;
}

// ------------------------------------------------------------------------------ 7-Scenes

// One OctoMap built node after node (one update per node, as the SLAM loop does), then rebuilt
// after a loop closure. Points = the occupied voxels inserted: each node's ground and obstacle
// cells (its 3D local grid, already voxel filtered at Grid/CellSize from the decimated depth
// image), moved to the world and counted once per map voxel of the node; each is the end of a
// ray the OctoMap casts (rays = cells, a little more than points when two cells of a node fall
// in one world voxel). Free updates = voxels the rays crossed, once per node. CPU times are the
// process's: the ray casting may use a second thread.
struct OctoMapRun {
  std::shared_ptr<OctoMap> map;
  long points = 0, free = 0, rays = 0;
  double ms = 0.0, cpuMs = 0.0, rebuildMs = 0.0, rebuildCpuMs = 0.0;
  int rebuilt = 0;
};
constexpr int kOctoMapRuns = 3;

OctoMapRun insertOctoMap(const OctoMapOptions& o, const std::map<int, LocalGrid>& grids,
                         const std::map<int, Transform>& poses) {
  OctoMapRun r;
  r.map = std::make_shared<OctoMap>(o);
  std::map<int, Transform> g;
  for (const auto& [id, lg] : grids) {
    r.map->addLocalGrid(id, lg);
    g[id] = poses.at(id);
    const double c0 = processCpuMs();
    const OctoMapUpdateSummary s = r.map->update(g);
    r.cpuMs += processCpuMs() - c0;
    r.points += s.pointsInserted;
    r.free += s.freeVoxelUpdates;
    r.rays += s.rayTracedPoints;
    r.ms += s.timeMs;
  }
  const Clock::time_point t = Clock::now();
  const double c0 = processCpuMs();
  r.rebuilt = r.map->update(corrected(g, 0)).nodesInserted;
  r.rebuildCpuMs = processCpuMs() - c0;
  r.rebuildMs = msSince(t);
  return r;
}

Json benchDepth(const std::string& path, const std::string& out) {
  Json j;
  std::printf("7-Scenes depth (%s)\n", path.c_str());
  std::unique_ptr<DatasetReader> reader = openDatasetReader("7scenes", path);
  std::vector<SensorData> frames;
  DatasetRecord rec;
  Transform first;
  while (reader->next(rec)) {
    if (rec.kind != DatasetRecord::Kind::kFrame || rec.data.groundTruth().isNull()) continue;
    // The world of KinectFusion is its first camera's; the base frame (ROS axes at the camera) of
    // the first frame gives a z-up world when the camera starts level.
    if (first.isNull()) first = rec.data.groundTruth();
    rec.data.setOdom(first.inverse() * rec.data.groundTruth(), Eigen::Matrix<double, 6, 6>::Identity());
    frames.push_back(rec.data);
  }
  std::printf("  %zu frames\n", frames.size());
  j["frames"] = frames.size();
  if (frames.empty()) return j;
  // Hand-held: the base is the camera, so heights are relative to it; levelled by the pose.
  const ParametersMap common{{"Grid/Sensor", "1"}, {"Grid/CellSize", "0.05"}, {"Grid/RangeMax", "4"},
                             {"Grid/MapFrameProjection", "true"}, {"Grid/DepthDecimation", "4"}};
  auto with = [&](ParametersMap p, const ParametersMap& extra) {
    for (const auto& [k, v] : extra) p[k] = v;
    return p;
  };
  struct Variant {
    const char* name;
    ParametersMap params;
  };
  const std::vector<Variant> variants = {
      {"2d", with(common, {{"Grid/3D", "false"}, {"Grid/RayTracing", "true"}})},
      {"3d", with(common, {{"Grid/3D", "true"}, {"Grid/RayTracing", "false"}})},
      {"3d_raytraced", with(common, {{"Grid/3D", "true"}, {"Grid/RayTracing", "true"}})},
  };
  std::map<std::string, std::map<int, LocalGrid>> grids;
  std::map<int, Transform> poses;
  for (size_t i = 0; i < frames.size(); ++i) poses[static_cast<int>(i) + 1] = frames[i].odomPose();
  for (const Variant& v : variants) {
    const LocalGridOptions lo = LocalGridOptions::fromParameters(v.params);
    Series ms, raw, compressed, points;
    std::map<std::string, double> stages;
    int failed = 0;
    for (size_t i = 0; i < frames.size(); ++i) {
      const Clock::time_point t = Clock::now();
      const LocalGridResult r = createLocalGrid(frames[i], lo);
      ms.add(msSince(t));
      if (!r.success) {
        ++failed;
        continue;
      }
      for (const auto& [stage, sms] : r.stats.stageMs) stages[stage] += sms / frames.size();
      const LocalGridBytes b = localGridBytes(r.grid);
      raw.add(b.raw);
      compressed.add(b.compressed);
      points.add(r.stats.groundCells + r.stats.obstacleCells);
      grids[v.name][static_cast<int>(i) + 1] = r.grid;
    }
    std::printf("  local grid %-13s %6.2f ms/frame (p95 %6.2f, %d failed); %7.0f B/node raw, %7.0f B/node compressed\n",
                v.name, ms.mean(), ms.pct(0.95), failed, raw.mean(), compressed.mean());
    j["local_grid_" + std::string(v.name)] = {{"ms", ms.json()}, {"failed", failed}, {"stage_ms", stages},
                                              {"bytes_per_node", {{"raw", raw.mean()}, {"compressed", compressed.mean()}}},
                                              {"cells_per_node", points.mean()}};
  }

  // 2D global grid.
  OccupancyGrid grid(GlobalGridOptions::fromParameters({{"Grid/CellSize", "0.05"}}));
  Series incremental;
  std::map<int, Transform> graph;
  for (const auto& [id, g] : grids["2d"]) {
    const Clock::time_point t = Clock::now();
    grid.addLocalGrid(id, g);
    graph[id] = poses.at(id);
    grid.update(graph);
    incremental.add(msSince(t));
  }
  std::printf("  2D incremental update per node: %.3f ms mean, %.3f ms p95\n", incremental.mean(), incremental.pct(0.95));
  j["grid2d_incremental_ms"] = incremental.json();
  j["grid2d_reassembly"] = reassembly(grid, graph, corrected(graph, 0), "2D re-assembly, every node moved:");
  grid.update(graph);
  Json picture;
  saveGrid(grid.map(), out, "7scenes_grid", picture);
  j["grid2d"] = picture;

  // OctoMap from the 3D grids without empty voxels (the global map casts the rays), and from
  // the grids with their empty voxels; each built several times, medians reported.
  for (const char* variant : {"3d", "3d_raytraced"}) {
    const OctoMapOptions oo = OctoMapOptions::fromParameters(
        {{"Grid/CellSize", "0.05"}, {"Grid/RayTracing", "true"}, {"Grid/RangeMax", "4"}});
    OctoMapRun last;
    Series rate, cpuRate, updatesCpuRate, msPerNode, rebuildMs, rebuildCpu;
    for (int run = 0; run < kOctoMapRuns; ++run) {
      last = insertOctoMap(oo, grids[variant], poses);
      rate.add(last.points / (last.ms / 1000.0));
      cpuRate.add(last.points / (last.cpuMs / 1000.0));
      updatesCpuRate.add((last.points + last.free) / (last.cpuMs / 1000.0));
      msPerNode.add(last.ms / std::max<size_t>(1, grids[variant].size()));
      rebuildMs.add(last.rebuildMs);
      rebuildCpu.add(last.rebuildCpuMs);
    }
    const OctoMap& octo = *last.map;
    const std::string label = std::string(variant) == "3d" ? "rays cast by the OctoMap" : "empty voxels from the local grids";
    std::printf("  OctoMap (%s), median of %d: %.2f M points/s (cpu %.2f M points/s, %.2f M voxel updates/s; %ld points, "
                "%ld rays, %ld free updates, %.1f ms/node); rebuild of %d nodes: %.0f ms (cpu %.0f); %zu leaves, %.1f MB\n",
                label.c_str(), kOctoMapRuns, rate.median() / 1e6, cpuRate.median() / 1e6, updatesCpuRate.median() / 1e6,
                last.points, last.rays, last.free, msPerNode.median(), last.rebuilt, rebuildMs.median(),
                rebuildCpu.median(), octo.leafCount(), octo.memoryUsed() / 1e6);
    Json oj = {{"points_per_second", rate.median()}, {"points_per_cpu_second", cpuRate.median()},
               {"voxel_updates_per_cpu_second", updatesCpuRate.median()}, {"points_per_cpu_second_runs", cpuRate.v},
               {"points", last.points}, {"rays", last.rays}, {"free_updates", last.free},
               {"ms_per_node", msPerNode.median()}, {"rebuild_ms", rebuildMs.median()},
               {"rebuild_cpu_ms", rebuildCpu.median()}, {"leaves", octo.leafCount()}, {"memory_bytes", octo.memoryUsed()}};
    if (std::string(variant) == "3d") {
      const GridMap proj = octo.projection2D(-1.5f, 0.3f);  // heights relative to the first camera
      if (!proj.empty()) {
        Json pic;
        saveGrid(proj, out, "7scenes_octomap_projection", pic);
        oj["projection"] = pic;
      }
      const std::string bt = (fs::path(out) / "7scenes.bt").string();
      octo.writeBinary(bt);
      oj["bt"] = bt;
    }
    j["octomap_" + std::string(variant)] = oj;
  }
  return j;
}

Settings parse(int argc, char** argv) {
  Settings s;
  s.argv0 = argv[0];
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench-maps_bench: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--out") s.out = value();
    else if (a == "--data") s.data = value();
    else if (a == "--max-scans") s.maxScans = std::stoi(value());
    else if (a == "--wheel-odometry") s.wheelOdometry = true;
    else if (a == "--only") s.only = value();
    else if (a == "--odometry-poses") s.odometryPoses = true;
    else if (a == "--slam-dir") s.slamDir = value();
    else {
      std::fprintf(stderr,
                   "usage: bench-maps_bench [--out DIR] [--data DIR] [--max-scans N] [--only intel|aces|7scenes]\n"
                   "                        [--odometry-poses [--wheel-odometry]] [--slam-dir DIR]\n");
      std::exit(a == "--help" || a == "-h" ? 0 : 2);
    }
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const Settings s = parse(argc, argv);
  setLogLevel(LogLevel::kError);
  const std::string data = dataDir(s), out = outputDir(s);
  fs::create_directories(out);
  Json j;
  j["bench"] = "maps";
  j["output_dir"] = out;
  std::printf("maps bench: data %s, images and maps written to %s\n", data.empty() ? "(none)" : data.c_str(), out.c_str());
  try {
    const std::vector<std::tuple<std::string, std::string, size_t>> logs = {
        {"intel", "radish/intel.clf.bz2", 1000}, {"aces", "radish/aces.clf.bz2", 1000}};
    for (const auto& [name, file, target] : logs) {
      if (!s.only.empty() && s.only != name) continue;
      const fs::path p = fs::path(data) / file;
      if (data.empty() || !fs::exists(p)) {
        std::printf("%s: skipped (%s not found)\n", name.c_str(), p.string().c_str());
        continue;
      }
      j[name] = benchLaser(name, p.string(), s, out, target);
    }
    const fs::path scenes = fs::path(data) / "rgbd_7scenes";
    if (!s.only.empty() && s.only != "7scenes") {
    } else if (!data.empty() && fs::is_directory(scenes)) j["7scenes"] = benchDepth(scenes.string(), out);
    else std::printf("7-Scenes: skipped (%s not found)\n", scenes.string().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench-maps_bench: error: %s\n", e.what());
    j["error"] = e.what();
    std::cout << j.dump() << std::endl;
    return 1;
  }
  std::cout << j.dump() << std::endl;
  return 0;
}

// bench-sim_bench: how fast does rtabmap-sim make frames at 640x480?
//
// In the loop scenario's building (full-resolution textures), at 200 poses along its route:
//   render      RGB + depth (one ray-cast view)
//   +stereo     RGB + depth + the right image of the stereo pair (a second view, to grey)
//   +lasers     + URG-04LX and UTM-30LX scans: everything a dataset frame holds by default
//   +lidar      + the 16-beam lidar sweep (optional in datasets)
// each as the median over frames of the wall-clock time per frame (fps = 1 / median), and the
// process CPU time per frame, whose inverse (cpu_fps: frames per CPU-second, what one dedicated
// core gives) does not depend on other load on the machine; the renderer runs on OpenCV's
// threads, so an idle multi-core machine does better than cpu_fps. Then the full pipeline:
//   write       the simulator driving the route and writing the dataset folder (PNG encoding on
//               2 threads, text files, scans): frames per second of wall-clock time.
// The 30 fps goal is for "+lasers": every sensor of a default dataset frame rendered (RGB,
// depth, right stereo image, both 2D scans), without disk writing. It is judged twice: on the
// wall clock (as measured, so only meaningful on an otherwise idle machine; the load average is
// printed) and on cpu_fps (one core's worth).
// Human-readable lines first, then one JSON line with every figure.
//
// Usage: bench-sim_bench [--frames N] [--write-seconds S] [--dir DIR]
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <unistd.h>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "rtabmap_core/sim/Building.h"
#include "rtabmap_core/sim/Motion.h"
#include "rtabmap_core/sim/RangeSensors.h"
#include "rtabmap_core/sim/Scenarios.h"
#include "rtabmap_core/sim/SimDatasetWriter.h"
#include "rtabmap_core/sim/Simulator.h"

namespace fs = std::filesystem;
using namespace rtabmap::sim;
using Clock = std::chrono::steady_clock;

namespace {

struct Figure {
  double fps = 0.0;         // 1 / median wall time per frame
  double medianMs = 0.0;
  double cpuMsPerFrame = 0.0;
  double cpuFps() const { return cpuMsPerFrame > 0.0 ? 1000.0 / cpuMsPerFrame : 0.0; }
};

// The 1-minute load average (-1 if unknown): says how far wall-clock figures are to be trusted.
double loadAverage() {
  double load[1];
  return ::getloadavg(load, 1) == 1 ? load[0] : -1.0;
}

double cpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

template <class F>
Figure measure(const std::vector<Pose2>& poses, F&& frame) {
  std::vector<double> times;
  const double cpu0 = cpuSeconds();
  for (const Pose2& p : poses) {
    const auto t0 = Clock::now();
    frame(p);
    times.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  const double cpu = cpuSeconds() - cpu0;
  std::nth_element(times.begin(), times.begin() + static_cast<std::ptrdiff_t>(times.size() / 2), times.end());
  Figure f;
  f.medianMs = 1000.0 * times[times.size() / 2];
  f.fps = 1000.0 / f.medianMs;
  f.cpuMsPerFrame = 1000.0 * cpu / static_cast<double>(poses.size());
  return f;
}

nlohmann::json toJson(const Figure& f) {
  return {{"fps", f.fps}, {"median_ms", f.medianMs}, {"cpu_ms_per_frame", f.cpuMsPerFrame}, {"cpu_fps", f.cpuFps()}};
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 200;
  double writeSeconds = 40.0;
  std::string dir;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--frames" && i + 1 < argc) frames = std::atoi(argv[++i]);
    else if (a == "--write-seconds" && i + 1 < argc) writeSeconds = std::atof(argv[++i]);
    else if (a == "--dir" && i + 1 < argc) dir = argv[++i];
    else {
      std::cerr << "usage: bench-sim_bench [--frames N] [--write-seconds S] [--dir DIR]\n";
      return 2;
    }
  }
  if (frames < 10 || writeSeconds <= 0.0) {
    std::cerr << "bench-sim_bench: --frames >= 10 and --write-seconds > 0\n";
    return 2;
  }

  const double loadBefore = loadAverage();
  const ScenarioSpec spec = scenarioSpec("loop");
  const auto g0 = Clock::now();
  const double gc0 = cpuSeconds();
  const Building building = generateBuilding(spec.building, 1);
  const double generation = std::chrono::duration<double>(Clock::now() - g0).count();
  const double generationCpu = cpuSeconds() - gc0;
  const auto routes = planRoutes(spec, building, 1, MotionLimits());
  const ReferencePath path(routes.front().waypoints, MotionLimits());

  // Poses spread along the route (the robot's true poses, as a run would render them).
  std::vector<Pose2> poses;
  {
    RobotSimulator robot(path);
    const long long every = std::max(1LL, static_cast<long long>(path.duration() * 1000.0 / frames));
    long long step = 0;
    while (!robot.finished() && static_cast<int>(poses.size()) < frames) {
      const RobotState& s = robot.step();
      if (++step % every == 0) poses.push_back(s.pose);
    }
  }

  SimulationConfig config;  // 640 x 480, defaults of a dataset
  const Renderer renderer(*building.world, config.camera.intrinsics, config.render);
  cv::Mat bgr, depth, right, grey;
  const Figure render = measure(poses, [&](const Pose2& p) { renderer.render(viewFrom(p, config.camera.baseToOptical), bgr, &depth); });
  const Figure stereo = measure(poses, [&](const Pose2& p) {
    renderer.render(viewFrom(p, config.camera.baseToOptical), bgr, &depth);
    renderer.render(viewFrom(p, config.camera.baseToRightOptical()), right);
    cv::cvtColor(right, grey, cv::COLOR_BGR2GRAY);
  });
  const Simulator simulator(*building.world, config);
  const Figure lasers = measure(poses, [&](const Pose2& p) { simulator.capture(p); });
  SimulationConfig withLidar = config;
  withLidar.lidar3d = true;
  const Simulator lidarSimulator(*building.world, withLidar);
  const Figure lidar = measure(poses, [&](const Pose2& p) { lidarSimulator.capture(p); });

  // The whole pipeline into a folder.
  const fs::path out = dir.empty() ? fs::temp_directory_path() / ("bench_sim_" + std::to_string(::getpid())) : fs::path(dir);
  SimulationConfig writeConfig = config;
  writeConfig.maxDuration = writeSeconds;
  SimDatasetInfo info;
  info.scenario = "loop";
  info.seed = 1;
  const Simulator writer(*building.world, writeConfig);
  double writeFps = 0.0, writeCpu = 0.0;
  int written = 0;
  uintmax_t bytes = 0;
  {
    SimDatasetWriter sink(out.string(), writeConfig, info, 2);
    const auto w0 = Clock::now();
    const double wc0 = cpuSeconds();
    const SessionSummary summary = writer.run(path, sink, 1);
    sink.finish(summary);
    const double wall = std::chrono::duration<double>(Clock::now() - w0).count();
    written = summary.frames;
    writeFps = summary.frames / wall;
    writeCpu = 1000.0 * (cpuSeconds() - wc0) / summary.frames;
    for (const auto& e : fs::recursive_directory_iterator(out)) {
      if (e.is_regular_file()) bytes += e.file_size();
    }
  }
  if (dir.empty()) fs::remove_all(out);

  const double lapFrames = 7200.0;  // the long scenario at 1 Hz
  const double loadAfter = loadAverage();
  auto line = [](const char* label, const Figure& f) {
    std::ostringstream out;
    out << "  " << label << f.fps << " fps (" << f.medianMs << " ms; " << f.cpuMsPerFrame << " ms CPU = " << f.cpuFps()
        << " frames per CPU-second)";
    return out.str();
  };
  std::cout << "rtabmap-sim frame rates at 640x480 (loop building: " << building.roomCount() << " rooms, generated in " << generation
            << " s, " << generationCpu << " s CPU), median over " << poses.size() << " frames; load average " << loadBefore
            << " before, " << loadAfter << " after:\n"
            << line("render RGB + depth:                 ", render) << "\n"
            << line("+ stereo right image:               ", stereo) << "\n"
            << line("+ URG and UTM scans (a full frame): ", lasers) << "   <- the 30 fps goal\n"
            << line("+ 16-beam lidar:                    ", lidar) << "\n"
            << "  written to disk (PNG, 2 threads):   " << writeFps << " fps over " << written << " frames (" << writeCpu
            << " ms CPU per frame, " << bytes / std::max(1, written) / 1024 << " KiB per frame)\n"
            << "  -> the long scenario (7200 frames) would take about " << lapFrames / writeFps / 60.0 << " minutes\n"
            << "  30 fps goal (full frame): " << (lasers.fps >= 30.0 ? "met" : "not met") << " on the wall clock, "
            << (lasers.cpuFps() >= 30.0 ? "met" : "not met") << " per CPU-second\n";
  nlohmann::json j = {{"bench", "sim"},
                      {"width", config.camera.intrinsics.width},
                      {"height", config.camera.intrinsics.height},
                      {"frames", poses.size()},
                      {"load_average", {loadBefore, loadAfter}},
                      {"generation_s", generation},
                      {"render_rgbd", toJson(render)},
                      {"render_stereo", toJson(stereo)},
                      {"render_full_frame", toJson(lasers)},
                      {"render_with_lidar", toJson(lidar)},
                      {"write_fps", writeFps},
                      {"write_cpu_ms_per_frame", writeCpu},
                      {"write_frames", written},
                      {"bytes_per_frame", bytes / std::max(1, written)},
                      {"goal_fps", 30.0},
                      {"goal_met_wall", lasers.fps >= 30.0},
                      {"goal_met_cpu", lasers.cpuFps() >= 30.0}};
  std::cout << j.dump() << std::endl;
  return 0;
}

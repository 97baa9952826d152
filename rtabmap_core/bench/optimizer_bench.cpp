// bench-optimizer_bench: does the pose-graph optimiser reach the optimum, fast?
//
// Runs the built rtabmap-g2o (next to this executable) with --json and default settings on
// every reference graph of ../shared/data/posegraphs, several times each, and prints a table:
// graph, poses, edges, final chi2, the best known g2o chi2 of the data README, the relative
// gap, the median optimisation time (initialisation included, file I/O excluded: the tool's
// time_s), the GTSAM time of the README (SE-Sync paper, Xeon E3-1505M), their ratio, and
// PASS/FAIL for the two goals of issue 4: gap within 1%, time within 2x GTSAM's. Then one JSON
// line with every figure. Also the median process CPU time (cpu s) and the load average: on a
// shared machine the wall-clock times grow with the load, the CPU times much less.
//
// Usage: bench-optimizer_bench [--runs N] [--data DIR] [--tool PATH] [-- extra rtabmap-g2o args]
// Skips (exit 0, with a message) when the data folder is absent.
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// From ../shared/data/README.md, "Reference optima for the pose graphs".
struct Reference {
  const char* name;
  double bestChi2;
  std::optional<double> gtsamSeconds;
};
const Reference kReferences[] = {
    {"intel", 45.0047, 0.120},
    {"manhattan", 3549.04, 0.268},
    {"city10000", 511.985, 1.670},
    {"sphere2500", 727.150, 0.704},
    {"parking-garage", 1.23869, 0.415},
    {"kitti_00", 98.322, std::nullopt},
};
constexpr double kChi2Tolerance = 0.01;  // within 1% of the best known value
constexpr double kTimeFactor = 2.0;      // within 2x GTSAM's time

struct Settings {
  int runs = 5;
  std::string data;
  std::string tool;
  std::vector<std::string> extra;
};

void usage() {
  std::cerr << "usage: bench-optimizer_bench [--runs N] [--data DIR] [--tool PATH] [-- ARGS]\n"
               "  --runs N     runs per graph; the time reported is their median (default 5)\n"
               "  --data DIR   the shared data folder (default: $RTABMAP_DATA_DIR, else a\n"
               "               ../shared/data beside a parent of this executable, of the current\n"
               "               folder or of the repository it was built from)\n"
               "  --tool PATH  rtabmap-g2o to run (default: the one next to this executable)\n"
               "  -- ARGS      extra arguments for rtabmap-g2o (e.g. -- --init tree)\n";
}

bool parse(int argc, char** argv, Settings& s) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool hasValue = i + 1 < argc;
    if (a == "--runs" && hasValue) {
      s.runs = std::atoi(argv[++i]);
    } else if (a == "--data" && hasValue) {
      s.data = argv[++i];
    } else if (a == "--tool" && hasValue) {
      s.tool = argv[++i];
    } else if (a == "--") {
      for (++i; i < argc; ++i) s.extra.push_back(argv[i]);
    } else {
      return false;
    }
  }
  return s.runs >= 1;
}

// Folders to search from: the one of argv[0] as typed (build/bin holds symlinks) and the one
// of the real executable.
std::vector<fs::path> executableDirs(const char* argv0) {
  std::vector<fs::path> dirs;
  std::error_code ec;
  const fs::path typed = fs::absolute(fs::path(argv0), ec).parent_path();
  if (!ec) dirs.push_back(typed);
  const fs::path real = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back(real.parent_path());
  return dirs;
}

std::string findTool(const char* argv0) {
  for (const fs::path& dir : executableDirs(argv0)) {
    const fs::path candidate = dir / "rtabmap-g2o";
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return "";
}

std::string findData(const char* argv0) {
  if (const char* env = std::getenv("RTABMAP_DATA_DIR"); env && *env) return env;
  std::vector<fs::path> starts = executableDirs(argv0);
  std::error_code ec;
  starts.push_back(fs::current_path(ec));
  // This source file's folder (symlinks resolved): the repository, beside ../shared.
  const fs::path source = fs::canonical(fs::path(__FILE__), ec);
  if (!ec) starts.push_back(source.parent_path());
  for (fs::path dir : starts) {
    for (; !dir.empty(); dir = dir.parent_path()) {
      for (const fs::path& candidate : {dir / ".." / "shared" / "data", dir / "shared" / "data"}) {
        if (fs::is_directory(candidate / "posegraphs", ec)) return fs::weakly_canonical(candidate, ec).string();
      }
      if (dir == dir.root_path()) break;
    }
  }
  return "";
}

std::string quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Runs the tool; returns its last stdout line parsed, or nullopt with the reason in *why.
std::optional<nlohmann::json> runTool(const Settings& s, const std::string& graph, std::string* why) {
  std::string command = quote(s.tool) + " --json";
  for (const std::string& e : s.extra) command += " " + quote(e);
  command += " " + quote(graph) + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) {
    *why = "cannot run " + s.tool;
    return std::nullopt;
  }
  std::string output;
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  std::string last, line;
  std::istringstream in(output);
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  try {
    nlohmann::json j = nlohmann::json::parse(last);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) *why = j.value("why", std::string("failed"));
    return j;
  } catch (const std::exception&) {
    *why = "no JSON line from rtabmap-g2o: " + last;
    return std::nullopt;
  }
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  Settings s;
  if (!parse(argc, argv, s)) {
    usage();
    return 2;
  }
  if (s.tool.empty()) s.tool = findTool(argv[0]);
  if (s.tool.empty()) {
    std::cerr << "bench-optimizer_bench: rtabmap-g2o not found next to this executable\n";
    return 1;
  }
  if (s.data.empty()) s.data = findData(argv[0]);
  const fs::path folder = fs::path(s.data) / "posegraphs";
  std::error_code ec;
  if (s.data.empty() || !fs::is_directory(folder, ec)) {
    std::cout << "bench-optimizer_bench: skipped, no pose graphs (../shared/data/posegraphs is "
                 "absent; set RTABMAP_DATA_DIR or --data)\n";
    nlohmann::json skipped{{"bench", "optimizer"}, {"skipped", true}};
    std::cout << skipped.dump() << std::endl;
    return 0;
  }

  // Times are wall clock: on a shared machine, the load average says how much to trust them
  // (cpu s, the process CPU time, is the steadier figure).
  std::string load;
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    char buffer[128] = {0};
    if (std::fgets(buffer, sizeof(buffer), f)) load = buffer;
    std::fclose(f);
    if (!load.empty() && load.back() == '\n') load.pop_back();
  }
  std::cout << "rtabmap-g2o: " << s.tool << "\ndata: " << folder.string() << "\nruns per graph: "
            << s.runs << " (time: median; optimisation alone incl. initialisation, file I/O "
               "excluded; wall clock, cpu s: process CPU time)\nload average: "
            << (load.empty() ? "unknown" : load) << "\n\n";
  std::cout << std::left << std::setw(15) << "graph" << std::right << std::setw(7) << "poses"
            << std::setw(7) << "edges" << std::setw(13) << "final chi2" << std::setw(12) << "best"
            << std::setw(11) << "gap" << std::setw(9) << "iters" << std::setw(9) << "time s"
            << std::setw(9) << "GTSAM s" << std::setw(7) << "ratio" << std::setw(7) << "chi2"
            << std::setw(7) << "time" << std::setw(8) << "cpu s" << "\n";

  nlohmann::json report{{"bench", "optimizer"},
                        {"runs", s.runs},
                        {"load_average", load},
                        {"graphs", nlohmann::json::array()}};
  bool allPass = true;
  for (const Reference& ref : kReferences) {
    const fs::path graph = folder / (std::string(ref.name) + ".g2o");
    nlohmann::json row{{"graph", ref.name}, {"best_chi2", ref.bestChi2}};
    if (ref.gtsamSeconds) row["gtsam_s"] = *ref.gtsamSeconds;
    if (!fs::exists(graph, ec)) {
      std::cout << std::left << std::setw(15) << ref.name << " absent, skipped\n";
      row["skipped"] = true;
      report["graphs"].push_back(row);
      continue;
    }
    std::vector<double> times, initTimes, cpuTimes;
    nlohmann::json first;
    std::string why;
    for (int run = 0; run < s.runs; ++run) {
      const auto j = runTool(s, graph.string(), &why);
      if (!j || !why.empty() || !j->value("success", false)) break;
      if (run == 0) first = *j;
      times.push_back(j->at("time_s").get<double>());
      initTimes.push_back(j->at("init_time_s").get<double>());
      cpuTimes.push_back(j->at("cpu_time_s").get<double>());
    }
    if (times.size() != static_cast<std::size_t>(s.runs)) {
      std::cout << std::left << std::setw(15) << ref.name << " FAILED: " << why << "\n";
      row["failed"] = why;
      report["graphs"].push_back(row);
      allPass = false;
      continue;
    }
    const double chi2 = first["final_chi2"].get<double>();
    const double gap = (chi2 - ref.bestChi2) / ref.bestChi2;
    const double time = median(times);
    const bool chi2Pass = std::fabs(gap) <= kChi2Tolerance;
    std::optional<double> ratio;
    if (ref.gtsamSeconds) ratio = time / *ref.gtsamSeconds;
    const bool timePass = !ratio || *ratio <= kTimeFactor;
    allPass = allPass && chi2Pass && timePass;

    std::ostringstream gapText, ratioText;
    gapText << std::showpos << std::scientific << std::setprecision(1) << gap;
    if (ratio) ratioText << std::fixed << std::setprecision(2) << *ratio;
    std::cout << std::left << std::setw(15) << ref.name << std::right << std::setw(7)
              << first["poses"].get<int>() << std::setw(7) << first["edges"].get<int>()
              << std::setw(13) << std::setprecision(6) << chi2 << std::setw(12) << ref.bestChi2
              << std::setw(11) << gapText.str() << std::setw(9) << first["iterations"].get<int>()
              << std::setw(9) << std::fixed << std::setprecision(3) << time << std::setw(9)
              << (ref.gtsamSeconds ? std::to_string(*ref.gtsamSeconds).substr(0, 5) : "-")
              << std::setw(7) << (ratio ? ratioText.str() : "-") << std::setw(7)
              << (chi2Pass ? "PASS" : "FAIL") << std::setw(7)
              << (ref.gtsamSeconds ? (timePass ? "PASS" : "FAIL") : "n/a") << std::setw(8)
              << std::setprecision(3) << median(cpuTimes) << "\n"
              << std::defaultfloat;

    row["poses"] = first["poses"];
    row["edges"] = first["edges"];
    row["final_chi2"] = chi2;
    row["initial_chi2"] = first["initial_chi2"];
    row["gap"] = gap;
    row["iterations"] = first["iterations"];
    row["converged"] = first["converged"];
    row["init"] = first["init"];
    row["threads"] = first["threads"];
    row["time_s"] = time;
    row["time_s_all"] = times;
    row["init_time_s"] = median(initTimes);
    row["cpu_time_s"] = median(cpuTimes);
    if (ratio) row["ratio_to_gtsam"] = *ratio;
    row["chi2_pass"] = chi2Pass;
    if (ref.gtsamSeconds) row["time_pass"] = timePass;
    report["graphs"].push_back(row);
  }
  report["all_pass"] = allPass;
  std::cout << "\n" << (allPass ? "all goals met" : "some goals NOT met") << "\n";
  std::cout << report.dump() << std::endl;
  return 0;
}

#include "sim/BagExport.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <vector>

#include "rtabmap_core/common/Error.h"

extern char** environ;

namespace fs = std::filesystem;

namespace rtabmap::tools::sim {

namespace {

bool executable(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0;
}

}  // namespace

std::string findBagConverter(const std::string& argv0) {
  const std::string name = "rtabmap-bag";
  std::vector<fs::path> dirs;
  if (argv0.find('/') != std::string::npos) dirs.push_back(fs::path(argv0).parent_path());
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back(self.parent_path());
  for (const auto& d : dirs) {
    if (executable(d / name)) return (d / name).string();
  }
  if (const char* path = std::getenv("PATH")) {
    std::istringstream entries(path);
    std::string dir;
    while (std::getline(entries, dir, ':')) {
      if (!dir.empty() && executable(fs::path(dir) / name)) return (fs::path(dir) / name).string();
    }
  }
  return "";
}

void runBagConverter(const std::string& converter, const std::string& datasetDir, const std::string& bagPath, bool quietStdout) {
  std::vector<std::string> args = {converter, "--format", "sim", datasetDir, bagPath};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quietStdout) posix_spawn_file_actions_adddup2(&actions, STDERR_FILENO, STDOUT_FILENO);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, converter.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  std::string command;
  for (const auto& a : args) command += (command.empty() ? "" : " ") + a;
  if (rc != 0) throw Error("cannot run " + command + ": " + std::strerror(rc));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw Error("waiting for " + command + ": " + std::strerror(errno));
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw Error(command + " failed (" + (WIFEXITED(status) ? "exit code " + std::to_string(WEXITSTATUS(status)) : std::string("killed")) +
                "); the dataset folder " + datasetDir + " was written");
  }
}

}  // namespace rtabmap::tools::sim

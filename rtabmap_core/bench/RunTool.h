#pragma once
// For benchmarks that run the command-line tools built next to them: a tool run with --json,
// its last stdout line parsed.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>

namespace rtabmap::bench {

// `<toolsDir>/<tool> <arguments> --json` (--json last: rtabmap-eval takes its sub-command
// first); throws on a failed run.
inline nlohmann::json runToolJson(const std::string& toolsDir, const std::string& tool, const std::string& arguments) {
  const std::string command =
      (std::filesystem::path(toolsDir) / tool).string() + " " + arguments + " --json 2>/dev/null";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run " + command);
  std::string out, last;
  char buffer[4096];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0) out.append(buffer, n);
  const int status = ::pclose(pipe);
  if (status != 0) throw std::runtime_error(command + " failed (status " + std::to_string(status) + ")");
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    if (!line.empty()) last = line;
  }
  return nlohmann::json::parse(last);
}

}  // namespace rtabmap::bench

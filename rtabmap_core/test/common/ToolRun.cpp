#include "common/ToolRun.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace rtabmap::test {

ToolRun runTool(const std::string& toolName, const std::string& arguments, const TempDir& dir) {
  const std::string errFile = dir.file("stderr_" + toolName + ".txt");
  const std::string command = toolPath(toolName) + " " + arguments + " 2>" + errFile;
  ToolRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.stdoutText.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(errFile);
  std::stringstream s;
  s << err.rdbuf();
  run.stderrText = s.str();
  return run;
}

nlohmann::json lastJsonLine(const std::string& text) {
  std::string line, last;
  std::istringstream in(text);
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return nlohmann::json::parse(last);
}

}  // namespace rtabmap::test

#pragma once
// Runs a built command-line tool (rtabmap-<name>) in a test and captures what it printed.
#include <nlohmann/json.hpp>

#include <string>

#include "common/TestData.h"

namespace rtabmap::test {

struct ToolRun {
  int exitCode = -1;  // -1: did not exit normally
  std::string stdoutText;
  std::string stderrText;
};

// `rtabmap-<toolName> <arguments>` through the shell; stderr goes through a file in dir.
ToolRun runTool(const std::string& toolName, const std::string& arguments, const TempDir& dir);

// The --json contract: the last non-empty stdout line parsed (throws if it is not JSON).
nlohmann::json lastJsonLine(const std::string& text);

}  // namespace rtabmap::test

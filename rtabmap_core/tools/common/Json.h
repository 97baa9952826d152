#pragma once
// The --json contract of the tools: one JSON object, compact, on ONE line, printed last on
// stdout, so scripts can take `tail -n 1` of the output and parse it.
#include <nlohmann/json.hpp>

#include <ostream>
#include <string>

namespace rtabmap::tools {

// value.dump() on one line. Invalid UTF-8 in strings (labels, paths read from old databases)
// is replaced by U+FFFD instead of throwing, so a summary is always printed.
std::string toJsonLine(const nlohmann::json& value);
// Writes toJsonLine(value) and a newline to out, then flushes.
void printJsonLine(const nlohmann::json& value, std::ostream& out);
void printJsonLine(const nlohmann::json& value);  // to std::cout

}  // namespace rtabmap::tools

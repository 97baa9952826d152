#include "common/Json.h"

#include <iostream>

namespace rtabmap::tools {

std::string toJsonLine(const nlohmann::json& value) {
  // indent -1: compact, no newline anywhere (strings escape their own newlines).
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void printJsonLine(const nlohmann::json& value, std::ostream& out) {
  out << toJsonLine(value) << '\n';
  out.flush();
}

void printJsonLine(const nlohmann::json& value) { printJsonLine(value, std::cout); }

}  // namespace rtabmap::tools

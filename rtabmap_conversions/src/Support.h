#pragma once
// Helpers shared by the conversion sources (not installed: private to the library).
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

namespace rtabmap_conversions::detail {

// Every fallible conversion reports why it failed through an optional string; this keeps the
// "if (error) *error = ..." pattern in one place and returns the empty result to the caller.
inline std::nullopt_t fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return std::nullopt;
}

template <typename Range>
bool allFinite(const Range& values) {
  for (const auto& v : values) {
    if (!std::isfinite(static_cast<double>(v))) return false;
  }
  return true;
}

// "[1, 2, 3]" for error messages about small arrays (K, D, P).
template <typename Range>
std::string listString(const Range& values) {
  std::ostringstream out;
  out << "[";
  bool first = true;
  for (const auto& v : values) {
    out << (first ? "" : ", ") << v;
    first = false;
  }
  out << "]";
  return out.str();
}

}  // namespace rtabmap_conversions::detail

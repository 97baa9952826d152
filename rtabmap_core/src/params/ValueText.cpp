#include "ValueText.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <system_error>

namespace rtabmap::value_text {
namespace {

// std::from_chars does not take a leading '+', which users do write ("+0.5").
const char* skipPlus(const char* begin, const char* end) {
  if (end - begin >= 2 && *begin == '+' && (std::isdigit(static_cast<unsigned char>(begin[1])) ||
                                            begin[1] == '.')) {
    return begin + 1;
  }
  return begin;
}

bool parsesCompletelyAsReal(const std::string& text, double& value) {
  const char* begin = skipPlus(text.data(), text.data() + text.size());
  const char* end = text.data() + text.size();
  if (begin == end) return false;
  auto [ptr, ec] = std::from_chars(begin, end, value);
  // Out of range still consumed the whole text: strtod tells overflow (inf, reported as not
  // finite by the callers) from underflow (1e-400 reads as 0, a valid tiny value).
  if (ec == std::errc::result_out_of_range && ptr == end) {
    value = std::strtod(std::string(begin, end).c_str(), nullptr);
    return true;
  }
  return ec == std::errc() && ptr == end;
}

template <typename Real>
std::string formatShortest(Real value) {
  char buffer[64];
  auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  if (ec != std::errc()) {
    std::ostringstream stream;
    stream << value;
    return stream.str();
  }
  return std::string(buffer, ptr);
}

}  // namespace

bool parseBool(const std::string& text, bool& value) {
  const std::string lower = toLower(text);
  if (lower == "true" || lower == "1") {
    value = true;
    return true;
  }
  if (lower == "false" || lower == "0") {
    value = false;
    return true;
  }
  return false;
}

bool parseInt(const std::string& text, int& value, std::string* problem) {
  const char* end = text.data() + text.size();
  const char* begin = skipPlus(text.data(), end);
  long long wide = 0;
  auto [ptr, ec] = std::from_chars(begin, end, wide);
  const bool allDigits = begin != end && ptr == end;
  if (allDigits && ec == std::errc() && wide >= std::numeric_limits<int>::min() &&
      wide <= std::numeric_limits<int>::max()) {
    value = static_cast<int>(wide);
    return true;
  }
  if (problem) {
    double real = 0;
    if (allDigits) {
      *problem = "too large for an int";
    } else if (!parsesCompletelyAsReal(text, real)) {
      *problem = "not a number";
    } else if (!std::isfinite(real)) {
      *problem = "not a finite number";
    } else if (std::isfinite(real) && std::abs(real) > std::numeric_limits<int>::max()) {
      *problem = "too large for an int";  // "1e12"
    } else {
      *problem = "not a whole number";
    }
  }
  return false;
}

bool parseReal(const std::string& text, double& value, std::string* problem) {
  double parsed = 0;
  if (!parsesCompletelyAsReal(text, parsed)) {
    if (problem) *problem = "not a number";
    return false;
  }
  if (!std::isfinite(parsed)) {
    if (problem) *problem = "not a finite number";
    return false;
  }
  value = parsed;
  return true;
}

bool parseNumberList(const std::string& text, std::vector<double>& values,
                     std::string* problem) {
  values.clear();
  std::istringstream stream(text);
  std::string item;
  while (stream >> item) {
    double number = 0;
    std::string why;
    if (!parseReal(item, number, &why)) {
      if (problem) *problem = "\"" + item + "\" is " + why;
      return false;
    }
    values.push_back(number);
  }
  return true;
}

std::string formatNumber(double value) { return formatShortest(value); }
std::string formatNumber(float value) { return formatShortest(value); }

std::string trim(const std::string& text) {
  const char* blanks = " \t\r\n\f\v";
  const auto first = text.find_first_not_of(blanks);
  if (first == std::string::npos) return "";
  const auto last = text.find_last_not_of(blanks);
  return text.substr(first, last - first + 1);
}

std::string toLower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

}  // namespace rtabmap::value_text

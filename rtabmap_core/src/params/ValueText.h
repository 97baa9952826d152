#pragma once
// Strict conversions between parameter text and values, shared by the params area. Strict
// because a typo in a launch file ("0,5", "1O", "ture") must be an error, not a silent 0.
#include <string>
#include <vector>

namespace rtabmap::value_text {

// true/false/1/0, ASCII case-insensitive. Returns false if the text is none of them.
bool parseBool(const std::string& text, bool& value);
// A whole decimal number fitting an int (optional sign). On failure, *problem says why:
// "not a number", "not a whole number" or "too large for an int".
bool parseInt(const std::string& text, int& value, std::string* problem);
// A finite decimal number ("1", "-0.5", "2.5e-05", optional '+'). On failure, *problem is
// "not a number" or "not a finite number" (nan, inf).
bool parseReal(const std::string& text, double& value, std::string* problem);
// Whitespace-separated finite numbers; false with *problem if one is not a number.
bool parseNumberList(const std::string& text, std::vector<double>& values, std::string* problem);

// Shortest text that reads back to the same value ("0.11", "1e-06", "3").
std::string formatNumber(double value);
std::string formatNumber(float value);

// Without leading and trailing spaces, tabs and carriage returns.
std::string trim(const std::string& text);
std::string toLower(std::string text);

}  // namespace rtabmap::value_text

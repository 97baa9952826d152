#pragma once
// The vocabulary of the "limits" column of params/groups/*.def. Only the registry table
// (Registry.cpp) evaluates that column, so these helpers stay private to the params area.
#include <string>

#include "rtabmap_core/params/ParameterInfo.h"

namespace rtabmap::param_limits {

inline ParameterLimits Any() { return {}; }

inline ParameterLimits AtLeast(double min) {
  ParameterLimits limits;
  limits.min = min;
  return limits;
}

inline ParameterLimits Above(double min) {
  ParameterLimits limits = AtLeast(min);
  limits.minExclusive = true;
  return limits;
}

inline ParameterLimits AtMost(double max) {
  ParameterLimits limits;
  limits.max = max;
  return limits;
}

inline ParameterLimits Range(double min, double max) {
  ParameterLimits limits;
  limits.min = min;
  limits.max = max;
  return limits;
}

inline ParameterChoice Choice(int value, const char* meaning) {
  return {std::to_string(value), meaning};
}

inline ParameterChoice Choice(const char* value, const char* meaning) { return {value, meaning}; }

template <typename... Choices>
ParameterLimits OneOf(Choices... choices) {
  ParameterLimits limits;
  limits.choices = {choices...};
  return limits;
}

// A string of whitespace-separated numbers: exactly `count` of them (0 = any count >= 1).
inline ParameterLimits NumberList(int count) {
  ParameterLimits limits;
  limits.numberListSize = count;
  return limits;
}

inline ParameterLimits NumberList(int count, double min, double max) {
  ParameterLimits limits = Range(min, max);
  limits.numberListSize = count;
  return limits;
}

// A parameter of the original not implemented here: only its default value is accepted.
inline ParameterLimits NotImplemented(const char* what) {
  ParameterLimits limits;
  limits.notImplemented = what;
  return limits;
}

}  // namespace rtabmap::param_limits

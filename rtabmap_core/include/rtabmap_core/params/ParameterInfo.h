#pragma once
// What the registry knows about one parameter: its key, type, default, description and the
// values it accepts. Built from the declarations in params/groups/*.def.
#include <optional>
#include <string>
#include <vector>

namespace rtabmap {

enum class ParameterType { kBool, kInt, kFloat, kDouble, kString };

// "bool", "int", "float", "double", "string".
const char* parameterTypeName(ParameterType type);

// One allowed value of an enumerated parameter, with what it means ("0", "Frame-to-Map").
struct ParameterChoice {
  std::string value;
  std::string meaning;
};

// The values a parameter accepts beyond its type. Numeric bounds apply to int/float/double
// values, and to each number of a number-list string. Empty limits accept any value of the type.
struct ParameterLimits {
  std::optional<double> min;
  std::optional<double> max;
  bool minExclusive = false;  // true: value > min, false: value >= min
  bool maxExclusive = false;
  // Non-empty: the parameter is an enumeration and the value must be one of these.
  std::vector<ParameterChoice> choices;
  // For string parameters holding whitespace-separated numbers (e.g. "0 0 0 0"): -1 when the
  // string is free text, 0 for any count >= 1, otherwise the exact count required.
  int numberListSize = -1;
  // Non-empty: a parameter of the original that this implementation does not have (declared so
  // that its launch files name it and get a clear answer): only its default is accepted, and
  // any other value is an error saying this.
  std::string notImplemented;
};

struct ParameterInfo {
  std::string key;    // "Group/Name"
  std::string group;  // "Group"
  std::string name;   // "Name"
  ParameterType type = ParameterType::kString;
  std::string defaultValue;  // as text, in the same form a user would write it
  std::string description;
  ParameterLimits limits;

  // What a valid value looks like, for messages: "an int >= 1", "a float in [0, 1]",
  // "one of 0 (Frame-to-Map), 1 (Frame-to-Frame)", "a bool (true/false/1/0)".
  std::string expectation() const;
};

}  // namespace rtabmap

// Checking values against their declaration, and typed access to parameter maps.
#include <cmath>
#include <limits>

#include "ValueText.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
namespace {

using value_text::formatNumber;

std::string describeBounds(const ParameterLimits& limits) {
  if (limits.min && limits.max) {
    return std::string(" in ") + (limits.minExclusive ? "(" : "[") + formatNumber(*limits.min) +
           ", " + formatNumber(*limits.max) + (limits.maxExclusive ? ")" : "]");
  }
  if (limits.min) return (limits.minExclusive ? " > " : " >= ") + formatNumber(*limits.min);
  if (limits.max) return (limits.maxExclusive ? " < " : " <= ") + formatNumber(*limits.max);
  return "";
}

std::string describeChoices(const ParameterInfo& info) {
  std::string text = "one of ";
  const bool quoted = info.type == ParameterType::kString;
  for (std::size_t i = 0; i < info.limits.choices.size(); ++i) {
    const ParameterChoice& choice = info.limits.choices[i];
    if (i > 0) text += ", ";
    text += quoted ? "\"" + choice.value + "\"" : choice.value;
    if (!choice.meaning.empty()) text += " (" + choice.meaning + ")";
  }
  return text;
}

bool withinBounds(const ParameterLimits& limits, double value) {
  if (limits.min && (limits.minExclusive ? value <= *limits.min : value < *limits.min)) {
    return false;
  }
  if (limits.max && (limits.maxExclusive ? value >= *limits.max : value > *limits.max)) {
    return false;
  }
  return true;
}

// The number an int/float/double value stands for; false with the reason if it is none.
bool parseNumeric(const ParameterInfo& info, const std::string& value, double& number,
                  std::string& problem) {
  if (info.type == ParameterType::kInt) {
    int integer = 0;
    if (!value_text::parseInt(value, integer, &problem)) return false;
    number = integer;
    return true;
  }
  if (!value_text::parseReal(value, number, &problem)) return false;
  if (info.type == ParameterType::kFloat && std::abs(number) > std::numeric_limits<float>::max()) {
    problem = "too large for a float";
    return false;
  }
  return true;
}

std::string problemWithNumberList(const ParameterInfo& info, const std::string& value) {
  std::vector<double> numbers;
  std::string problem;
  if (!value_text::parseNumberList(value, numbers, &problem)) return problem;
  const int expected = info.limits.numberListSize;
  if (numbers.empty()) return "no number";
  if (expected > 0 && static_cast<int>(numbers.size()) != expected) {
    return std::to_string(numbers.size()) + " numbers instead of " + std::to_string(expected);
  }
  for (double number : numbers) {
    if (!withinBounds(info.limits, number)) return formatNumber(number) + " is out of range";
  }
  return "";
}

bool matchesChoice(const ParameterInfo& info, const std::string& value, double number) {
  for (const ParameterChoice& choice : info.limits.choices) {
    if (info.type == ParameterType::kString) {
      if (choice.value == value) return true;
    } else {
      double allowed = 0;
      std::string ignored;
      if (parseNumeric(info, choice.value, allowed, ignored) && allowed == number) return true;
    }
  }
  return false;
}

// The value means the default (true / 1, 2 / 2.0...), for the parameters that accept only it.
bool isDefaultValue(const ParameterInfo& info, const std::string& value) {
  switch (info.type) {
    case ParameterType::kBool: {
      bool a = false, b = false;
      return value_text::parseBool(value, a) && value_text::parseBool(info.defaultValue, b) && a == b;
    }
    case ParameterType::kString:
      return value == info.defaultValue;
    default: {
      double a = 0, b = 0;
      std::string ignored;
      return parseNumeric(info, value, a, ignored) && parseNumeric(info, info.defaultValue, b, ignored) && a == b;
    }
  }
  return false;
}

// "" if the value suits the declaration's type and limits, else a short reason ("not a whole number").
std::string problemWithType(const ParameterInfo& info, const std::string& value) {
  switch (info.type) {
    case ParameterType::kBool: {
      bool ignored = false;
      return value_text::parseBool(value, ignored) ? "" : "not a bool";
    }
    case ParameterType::kString:
      if (info.limits.numberListSize >= 0) return problemWithNumberList(info, value);
      if (!info.limits.choices.empty() && !matchesChoice(info, value, 0)) {
        return "not an allowed value";
      }
      return "";
    default: {
      double number = 0;
      std::string problem;
      if (!parseNumeric(info, value, number, problem)) return problem;
      if (!info.limits.choices.empty()) {
        return matchesChoice(info, value, number) ? "" : "not an allowed value";
      }
      return withinBounds(info.limits, number) ? "" : "out of range";
    }
  }
}

// "" if the value suits the declaration, else a short reason; a parameter not implemented here
// accepts only its default.
std::string problemWith(const ParameterInfo& info, const std::string& value) {
  const std::string problem = problemWithType(info, value);
  if (!problem.empty() || info.limits.notImplemented.empty() || isDefaultValue(info, value)) return problem;
  return "not implemented here (" + info.limits.notImplemented + ")";
}

std::string invalidValueMessage(const ParameterInfo& info, const std::string& value,
                                const std::string& problem) {
  return "invalid value \"" + value + "\" for parameter " + info.key + ": " + problem +
         "; expected " + info.expectation() + " (default \"" + info.defaultValue + "\")";
}

// The text to read for a key: the map's value if present (validated), else the default.
const std::string& valueOrDefault(const ParametersMap& parameters, const ParameterInfo& info) {
  const auto it = parameters.find(info.key);
  if (it == parameters.end()) return info.defaultValue;
  const std::string problem = problemWith(info, it->second);
  if (!problem.empty()) throw ParameterError(invalidValueMessage(info, it->second, problem));
  return it->second;
}

const ParameterInfo& requireNumeric(const std::string& key, const char* getter) {
  const ParameterInfo& info = Parameters::info(key);
  if (info.type != ParameterType::kInt && info.type != ParameterType::kFloat &&
      info.type != ParameterType::kDouble) {
    throw ParameterError(std::string("parameter ") + key + " is a " +
                         parameterTypeName(info.type) + ", it cannot be read with " + getter);
  }
  return info;
}

const ParameterInfo& requireType(const std::string& key, ParameterType type, const char* getter) {
  const ParameterInfo& info = Parameters::info(key);
  if (info.type != type) {
    throw ParameterError(std::string("parameter ") + key + " is a " +
                         parameterTypeName(info.type) + ", it cannot be read with " + getter);
  }
  return info;
}

double readNumber(const ParametersMap& parameters, const ParameterInfo& info) {
  double number = 0;
  std::string ignored;
  parseNumeric(info, valueOrDefault(parameters, info), number, ignored);
  return number;
}

}  // namespace

std::string ParameterInfo::expectation() const {
  if (!limits.notImplemented.empty()) return "its default only (not implemented here)";
  if (!limits.choices.empty()) return describeChoices(*this);
  switch (type) {
    case ParameterType::kBool: return "a bool (true, false, 1 or 0)";
    case ParameterType::kInt: return "an int" + describeBounds(limits);
    case ParameterType::kFloat: return "a float" + describeBounds(limits);
    case ParameterType::kDouble: return "a double" + describeBounds(limits);
    case ParameterType::kString:
      if (limits.numberListSize < 0) return "text";
      return (limits.numberListSize == 0 ? std::string("numbers")
                                         : std::to_string(limits.numberListSize) + " numbers") +
             " separated by spaces" +
             (limits.min || limits.max ? ", each" + describeBounds(limits) : "");
  }
  return "";
}

bool Parameters::isValid(const std::string& key, const std::string& value, std::string* why) {
  try {
    validate(key, value);
    return true;
  } catch (const ParameterError& error) {
    if (why) *why = error.what();
    return false;
  }
}

void Parameters::validate(const std::string& key, const std::string& value) {
  const ParameterInfo& parameter = info(key);
  const std::string problem = problemWith(parameter, value);
  if (!problem.empty()) throw ParameterError(invalidValueMessage(parameter, value, problem));
}

void Parameters::validate(const ParametersMap& parameters) {
  std::vector<std::string> errors;
  for (const auto& [key, value] : parameters) {
    std::string why;
    if (!isValid(key, value, &why)) errors.push_back(why);
  }
  if (errors.empty()) return;
  if (errors.size() == 1) throw ParameterError(errors.front());
  std::string message = std::to_string(errors.size()) + " invalid parameters:";
  for (const std::string& error : errors) message += "\n  " + error;
  throw ParameterError(message);
}

bool Parameters::getBool(const ParametersMap& parameters, const std::string& key) {
  const ParameterInfo& info = requireType(key, ParameterType::kBool, "getBool");
  bool value = false;
  value_text::parseBool(valueOrDefault(parameters, info), value);
  return value;
}

int Parameters::getInt(const ParametersMap& parameters, const std::string& key) {
  const ParameterInfo& info = requireType(key, ParameterType::kInt, "getInt");
  return static_cast<int>(readNumber(parameters, info));
}

float Parameters::getFloat(const ParametersMap& parameters, const std::string& key) {
  return static_cast<float>(readNumber(parameters, requireNumeric(key, "getFloat")));
}

double Parameters::getDouble(const ParametersMap& parameters, const std::string& key) {
  return readNumber(parameters, requireNumeric(key, "getDouble"));
}

std::string Parameters::getString(const ParametersMap& parameters, const std::string& key) {
  return valueOrDefault(parameters, info(key));
}

std::vector<double> Parameters::getNumberList(const ParametersMap& parameters,
                                              const std::string& key) {
  const ParameterInfo& parameter = info(key);
  if (parameter.limits.numberListSize < 0) {
    throw ParameterError("parameter " + key + " is not a list of numbers, it cannot be read with "
                         "getNumberList");
  }
  std::vector<double> numbers;
  value_text::parseNumberList(valueOrDefault(parameters, parameter), numbers, nullptr);
  return numbers;
}

ParametersMap Parameters::filterByGroup(const ParametersMap& parameters,
                                        const std::string& group) {
  const std::string prefix = group + "/";
  ParametersMap filtered;
  for (auto it = parameters.lower_bound(prefix);
       it != parameters.end() && it->first.compare(0, prefix.size(), prefix) == 0; ++it) {
    filtered.insert(*it);
  }
  return filtered;
}

ParametersMap Parameters::withDefaults(const ParametersMap& parameters) {
  validate(parameters);
  ParametersMap merged = defaults();
  for (const auto& [key, value] : parameters) merged[key] = value;
  return merged;
}

}  // namespace rtabmap

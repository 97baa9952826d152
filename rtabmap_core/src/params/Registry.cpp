// The registry table, generated from params/groups/*.def, and lookups in it.
#include <algorithm>
#include <unordered_map>

#include "Limits.h"
#include "ValueText.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/params/ClosestMatch.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
namespace {

template <typename T>
ParameterType typeOf();
template <>
ParameterType typeOf<bool>() { return ParameterType::kBool; }
template <>
ParameterType typeOf<int>() { return ParameterType::kInt; }
template <>
ParameterType typeOf<float>() { return ParameterType::kFloat; }
template <>
ParameterType typeOf<double>() { return ParameterType::kDouble; }
template <>
ParameterType typeOf<std::string>() { return ParameterType::kString; }

// Defaults are written as C++ literals in the .def files; the registry keeps their text in the
// form a user would type, produced from the typed value so both always agree.
std::string defaultText(bool value) { return value ? "true" : "false"; }
std::string defaultText(int value) { return std::to_string(value); }
std::string defaultText(float value) { return value_text::formatNumber(value); }
std::string defaultText(double value) { return value_text::formatNumber(value); }
std::string defaultText(const std::string& value) { return value; }

ParameterInfo declare(const char* group, const char* name, ParameterType type,
                      std::string defaultValue, ParameterLimits limits, const char* description) {
  ParameterInfo info;
  info.group = group;
  info.name = name;
  info.key = info.group + "/" + info.name;
  info.type = type;
  info.defaultValue = std::move(defaultValue);
  info.description = description;
  info.limits = std::move(limits);
  return info;
}

std::vector<ParameterInfo> declarations() {
  using namespace param_limits;
  return {
#define RTABMAP_PARAM(GROUP, NAME, TYPE, DEFAULT, LIMITS, DESCRIPTION)                     \
  declare(#GROUP, #NAME, typeOf<TYPE>(), defaultText(static_cast<TYPE>(DEFAULT)), LIMITS, \
          DESCRIPTION),
#include "rtabmap_core/params/ParameterList.def"
#undef RTABMAP_PARAM
  };
}

struct Registry {
  std::vector<ParameterInfo> all;  // sorted by key
  std::unordered_map<std::string, std::size_t> indexByKey;
  ParametersMap defaults;
  std::vector<std::string> keys;

  Registry() : all(declarations()) {
    std::sort(all.begin(), all.end(),
              [](const ParameterInfo& a, const ParameterInfo& b) { return a.key < b.key; });
    for (std::size_t i = 0; i < all.size(); ++i) {
      indexByKey.emplace(all[i].key, i);
      defaults.emplace(all[i].key, all[i].defaultValue);
      keys.push_back(all[i].key);
    }
  }
};

const Registry& registry() {
  static const Registry instance;
  return instance;
}

std::string namePart(const std::string& key) {
  const auto slash = key.find_last_of("/\\");
  return slash == std::string::npos ? key : key.substr(slash + 1);
}

}  // namespace

const std::vector<ParameterInfo>& Parameters::all() { return registry().all; }

const ParameterInfo* Parameters::find(const std::string& key) {
  const auto& index = registry().indexByKey;
  const auto it = index.find(key);
  return it == index.end() ? nullptr : &registry().all[it->second];
}

const ParameterInfo& Parameters::info(const std::string& key) {
  if (const ParameterInfo* found = find(key)) return *found;
  std::string message = "unknown parameter \"" + key + "\"";
  if (key.find('/') == std::string::npos) message += ", keys have the form Group/Name";
  message += " (did you mean \"" + closestKey(key) + "\"?)";
  throw ParameterError(message);
}

const ParametersMap& Parameters::defaults() { return registry().defaults; }

std::vector<std::string> Parameters::groups() {
  std::vector<std::string> names;
  for (const ParameterInfo& info : all()) {
    if (names.empty() || names.back() != info.group) names.push_back(info.group);
  }
  return names;
}

std::string Parameters::closestKey(const std::string& key) {
  // A user who typed the right name in the wrong group (or without a group) meant that name:
  // prefer keys whose name part matches exactly, nearest overall among them.
  const std::string name = value_text::toLower(namePart(key));
  std::vector<std::string> sameName;
  for (const std::string& candidate : registry().keys) {
    if (value_text::toLower(namePart(candidate)) == name) sameName.push_back(candidate);
  }
  return closestMatch(key, sameName.empty() ? registry().keys : sameName);
}

const char* parameterTypeName(ParameterType type) {
  switch (type) {
    case ParameterType::kBool: return "bool";
    case ParameterType::kInt: return "int";
    case ParameterType::kFloat: return "float";
    case ParameterType::kDouble: return "double";
    case ParameterType::kString: return "string";
  }
  return "unknown";
}

}  // namespace rtabmap

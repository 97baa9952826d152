// "--Group/Name value" command-line arguments.
#include <cctype>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
namespace {

// "--Rtabmap/DetectionRate" or "--Rtabmap/DetectionRate=2": a double dash, then a name with a
// slash before any '=' (tool options like "--output=/tmp/x" have no slash in their name).
bool isParameterArgument(const std::string& argument) {
  if (argument.size() < 4 || argument.compare(0, 2, "--") != 0) return false;
  const std::string name = argument.substr(2, argument.find('=') - 2);
  return !name.empty() && std::isalpha(static_cast<unsigned char>(name[0])) &&
         name.find('/') != std::string::npos;
}

bool looksLikeOption(const std::string& argument) { return argument.compare(0, 2, "--") == 0; }

}  // namespace

ParsedArguments Parameters::parseArguments(const std::vector<std::string>& args) {
  ParsedArguments parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& argument = args[i];
    if (argument == "--") {
      parsed.remaining.insert(parsed.remaining.end(), args.begin() + i, args.end());
      break;
    }
    if (!isParameterArgument(argument)) {
      parsed.remaining.push_back(argument);
      continue;
    }
    const auto equal = argument.find('=');
    const std::string key = argument.substr(2, equal == std::string::npos ? equal : equal - 2);
    const ParameterInfo* parameter = find(key);
    if (!parameter) {
      throw ParameterError("argument --" + key + ": unknown parameter \"" + key +
                           "\" (did you mean --" + closestKey(key) + "?)");
    }
    std::string value;
    if (equal != std::string::npos) {
      value = argument.substr(equal + 1);
    } else if (i + 1 < args.size() && !looksLikeOption(args[i + 1])) {
      value = args[++i];
    } else {
      throw ParameterError("argument --" + key + " needs a value: " + parameter->expectation() +
                           ", e.g. --" + key + " " + parameter->defaultValue);
    }
    std::string why;
    if (!isValid(key, value, &why)) throw ParameterError("argument --" + key + ": " + why);
    parsed.parameters[key] = value;
  }
  return parsed;
}

ParsedArguments Parameters::parseArguments(int argc, const char* const argv[]) {
  std::vector<std::string> args;
  for (int i = 1; i < argc; ++i) args.emplace_back(argv[i]);
  return parseArguments(args);
}

}  // namespace rtabmap

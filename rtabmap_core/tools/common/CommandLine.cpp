#include "common/CommandLine.h"

#include <cctype>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/Json.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/params/ClosestMatch.h"

namespace rtabmap::tools {
namespace {

constexpr std::size_t kHelpColumn = 26;  // where option descriptions start in --help
constexpr std::size_t kHelpWidth = 100;  // where they wrap

bool startsWith(const std::string& text, const char* prefix) {
  return text.rfind(prefix, 0) == 0;
}

// "-x..." looks like an option (unknown ones are errors); "-", "-5" and "-.5" are values.
bool looksLikeOption(const std::string& argument) {
  return argument.size() > 1 && argument[0] == '-' &&
         (argument[1] == '-' || std::isalpha(static_cast<unsigned char>(argument[1])));
}

// "  --name VALUE     help text", the help wrapped at kHelpWidth and aligned on kHelpColumn.
std::string helpLine(const std::string& left, const std::string& help) {
  std::string text = "  " + left;
  if (text.size() + 2 > kHelpColumn) text += "\n" + std::string(kHelpColumn, ' ');
  else text += std::string(kHelpColumn - text.size(), ' ');
  std::size_t column = kHelpColumn;
  std::istringstream words(help);
  std::string word;
  bool first = true;
  while (words >> word) {
    if (!first && column + 1 + word.size() > kHelpWidth) {
      text += "\n" + std::string(kHelpColumn, ' ');
      column = kHelpColumn;
    } else if (!first) {
      text += ' ';
      ++column;
    }
    text += word;
    column += word.size();
    first = false;
  }
  return text + "\n";
}

nlohmann::json parameterToJson(const ParameterInfo& parameter) {
  nlohmann::json entry = {{"key", parameter.key},
                          {"type", parameterTypeName(parameter.type)},
                          {"default", parameter.defaultValue},
                          {"expected", parameter.expectation()},
                          {"description", parameter.description}};
  const ParameterLimits& limits = parameter.limits;
  if (limits.min) entry[limits.minExclusive ? "above" : "min"] = *limits.min;
  if (limits.max) entry[limits.maxExclusive ? "below" : "max"] = *limits.max;
  if (!limits.choices.empty()) {
    nlohmann::json choices = nlohmann::json::array();
    for (const ParameterChoice& choice : limits.choices) {
      choices.push_back({{"value", choice.value}, {"meaning", choice.meaning}});
    }
    entry["choices"] = choices;
  }
  return entry;
}

}  // namespace

CommandLine::CommandLine(std::string toolName, std::string summary)
    : toolName_(std::move(toolName)), summary_(std::move(summary)) {
  // Built-in options every tool has; tools cannot redeclare these names.
  declareOption({"help", "", "Print this help and exit.", false, std::nullopt, std::nullopt});
  declareOption({"params", "",
                 "Print every core parameter with its default, accepted values and description, "
                 "then exit.",
                 false, std::nullopt, std::nullopt});
  declareOption({"json", "",
                 "Print a one-line JSON summary as the last line of stdout (and no progress "
                 "bar).",
                 false, std::nullopt, std::nullopt});
  declareOption({"config", "FILE",
                 "Read core parameters from the [Core] section of an INI file; --Group/Name "
                 "arguments override it.",
                 true, std::nullopt, std::nullopt});
  declareOption({"verbose", "", "Also print informational log messages on stderr.", false,
                 std::nullopt, std::nullopt});
  declareOption({"debug", "", "Also print debug log messages on stderr (e.g. why each proximity or "
                 "loop closure registration was rejected); implies --verbose.",
                 false, std::nullopt, std::nullopt});
}

void CommandLine::declareOption(Option option) {
  if (option.name.empty() || option.name[0] == '-' || option.name.find('/') != std::string::npos) {
    throw std::logic_error("option name \"" + option.name + "\" must be given without dashes "
                           "and cannot contain '/'");
  }
  if (findOption(option.name)) {
    throw std::logic_error("option --" + option.name + " is declared twice");
  }
  options_.push_back(std::move(option));
}

CommandLine& CommandLine::addFlag(const std::string& name, const std::string& help) {
  declareOption({name, "", help, false, std::nullopt, std::nullopt});
  return *this;
}

CommandLine& CommandLine::addOption(const std::string& name, const std::string& valueName,
                                    const std::string& help,
                                    std::optional<std::string> defaultValue) {
  declareOption({name, valueName.empty() ? "VALUE" : valueName, help, true,
                 std::move(defaultValue), std::nullopt});
  return *this;
}

CommandLine& CommandLine::addPositional(const std::string& name, const std::string& help,
                                        bool required) {
  if (!positionals_.empty() && positionals_.back().list) {
    throw std::logic_error("positional " + name + " declared after a positional list");
  }
  if (required && !positionals_.empty() && !positionals_.back().required) {
    throw std::logic_error("required positional " + name + " declared after an optional one");
  }
  positionals_.push_back({name, help, required, false, 0, {}});
  return *this;
}

CommandLine& CommandLine::addPositionalList(const std::string& name, const std::string& help,
                                            std::size_t minCount) {
  if (!positionals_.empty() && positionals_.back().list) {
    throw std::logic_error("only one positional list can be declared");
  }
  positionals_.push_back({name, help, minCount > 0, true, minCount, {}});
  return *this;
}

CommandLine& CommandLine::addNote(const std::string& text) {
  notes_.push_back(text);
  return *this;
}

CommandLine::Option* CommandLine::findOption(const std::string& name) {
  for (Option& option : options_) {
    if (option.name == name) return &option;
  }
  return nullptr;
}

const CommandLine::Option& CommandLine::declaredOption(const std::string& name) const {
  for (const Option& option : options_) {
    if (option.name == name) return option;
  }
  throw std::logic_error(toolName_ + " reads option --" + name + " which it never declared");
}

const CommandLine::Positional& CommandLine::declaredPositional(const std::string& name) const {
  for (const Positional& positional : positionals_) {
    if (positional.name == name) return positional;
  }
  throw std::logic_error(toolName_ + " reads positional " + name + " which it never declared");
}

bool CommandLine::parseOrThrow(const std::vector<std::string>& args) {
  // Help first: it must work even on a command line that is otherwise wrong.
  for (const std::string& argument : args) {
    if (argument == "--") break;
    if (argument == "--help" || argument == "-h") {
      help_ = true;
      return true;
    }
  }
  ParsedArguments parsed = Parameters::parseArguments(args);

  std::vector<std::string> positionalValues;
  const std::vector<std::string>& rest = parsed.remaining;
  for (std::size_t i = 0; i < rest.size(); ++i) {
    const std::string& argument = rest[i];
    if (argument == "--") {
      positionalValues.insert(positionalValues.end(), rest.begin() + i + 1, rest.end());
      break;
    }
    if (!looksLikeOption(argument)) {
      positionalValues.push_back(argument);
      continue;
    }
    i = takeOption(rest, i);
  }

  json_ = flag("json");
  params_ = flag("params");
  if (const Option& config = declaredOption("config"); config.value) {
    parameters_ = Parameters::readIni(*config.value);
  }
  for (const auto& [key, value] : parsed.parameters) parameters_[key] = value;
  if (params_) return true;  // like --help: the tool's own arguments are not needed
  assignPositionals(positionalValues);
  return false;
}

std::size_t CommandLine::takeOption(const std::vector<std::string>& args, std::size_t index) {
  const std::string& argument = args[index];
  const bool longForm = startsWith(argument, "--");
  const std::string body = argument.substr(longForm ? 2 : 1);
  const auto equal = body.find('=');
  const std::string name = body.substr(0, equal);
  Option* option = longForm ? findOption(name) : nullptr;
  if (!option) {
    std::vector<std::string> names;
    for (const Option& declared : options_) names.push_back(declared.name);
    throw UsageError("unknown option " + argument.substr(0, argument.find('=')) +
                     " (did you mean --" + closestMatch(name, names) + "?)");
  }
  if (!option->takesValue) {
    if (equal != std::string::npos) throw UsageError("option --" + name + " takes no value");
    option->value = "1";
  } else if (equal != std::string::npos) {
    option->value = body.substr(equal + 1);
  } else if (index + 1 < args.size() && !startsWith(args[index + 1], "--")) {
    option->value = args[++index];
  } else {
    throw UsageError("option --" + name + " needs a value (--" + name + " " +
                     option->valueName + ")");
  }
  return index;
}

void CommandLine::assignPositionals(const std::vector<std::string>& values) {
  std::size_t next = 0;
  for (Positional& positional : positionals_) {
    if (positional.list) {
      positional.values.assign(values.begin() + next, values.end());
      next = values.size();
      if (positional.values.size() < positional.minCount) {
        throw UsageError("expected at least " + std::to_string(positional.minCount) + " " +
                         positional.name + " argument(s), got " +
                         std::to_string(positional.values.size()));
      }
      continue;
    }
    if (next < values.size()) {
      positional.values = {values[next++]};
    } else if (positional.required) {
      throw UsageError("missing argument " + positional.name + ": " + positional.help);
    }
  }
  if (next < values.size()) {
    throw UsageError("unexpected argument \"" + values[next] + "\"");
  }
}

std::optional<int> CommandLine::parse(int argc, const char* const argv[], std::ostream& out,
                                      std::ostream& err) {
  std::vector<std::string> args;
  for (int i = 1; i < argc; ++i) args.emplace_back(argv[i]);
  try {
    if (parseOrThrow(args)) {
      if (help_) {
        out << helpText();
      } else {
        printParameters(out, json_, parameters_);
      }
      return kExitSuccess;
    }
  } catch (const Error& error) {  // UsageError, ParameterError (unknown key, bad value, INI)
    err << toolName_ << ": error: " << error.what() << "\n"
        << "Run '" << toolName_ << " --help' for usage, '" << toolName_
        << " --params' for the core parameters.\n";
    return kExitUsage;
  }
  if (flag("debug")) {
    setLogLevel(LogLevel::kDebug);
  } else if (flag("verbose")) {
    setLogLevel(LogLevel::kInfo);
  }
  return std::nullopt;
}

std::optional<int> CommandLine::parse(int argc, char** argv) {
  return parse(argc, argv, std::cout, std::cerr);
}

bool CommandLine::flag(const std::string& name) const {
  const Option& option = declaredOption(name);
  if (option.takesValue) {
    throw std::logic_error("option --" + name + " takes a value; read it with option()");
  }
  return option.value.has_value();
}

bool CommandLine::has(const std::string& name) const {
  const Option& option = declaredOption(name);
  return option.value.has_value() || option.defaultValue.has_value();
}

std::string CommandLine::option(const std::string& name) const {
  const Option& option = declaredOption(name);
  if (option.value) return *option.value;
  if (option.defaultValue) return *option.defaultValue;
  throw UsageError("option --" + name + " is required (--" + name + " " + option.valueName + ")");
}

int CommandLine::optionInt(const std::string& name) const {
  const std::string text = option(name);
  try {
    std::size_t used = 0;
    const long value = std::stol(text, &used);
    if (used == text.size() && value >= std::numeric_limits<int>::min() &&
        value <= std::numeric_limits<int>::max()) {
      return static_cast<int>(value);
    }
  } catch (const std::exception&) {
  }
  throw UsageError("option --" + name + " expects a whole number, got \"" + text + "\"");
}

double CommandLine::optionDouble(const std::string& name) const {
  const std::string text = option(name);
  try {
    std::size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size() && std::isfinite(value)) return value;
  } catch (const std::exception&) {
  }
  throw UsageError("option --" + name + " expects a number, got \"" + text + "\"");
}

std::string CommandLine::positional(const std::string& name) const {
  const Positional& positional = declaredPositional(name);
  if (positional.list) {
    throw std::logic_error(name + " is a positional list; read it with positionalList()");
  }
  return positional.values.empty() ? "" : positional.values.front();
}

std::vector<std::string> CommandLine::positionalList(const std::string& name) const {
  return declaredPositional(name).values;
}

std::string CommandLine::synopsis() const {
  std::string text = "Usage: " + toolName_ + " [options] [--Group/Name value ...]";
  for (const Positional& positional : positionals_) {
    std::string shown = positional.name + (positional.list ? " ..." : "");
    text += " " + (positional.required ? shown : "[" + shown + "]");
  }
  return text + "\n";
}

std::string CommandLine::helpText() const {
  std::ostringstream text;
  text << synopsis() << "\n" << summary_ << "\n";
  if (!positionals_.empty()) {
    text << "\nArguments:\n";
    for (const Positional& positional : positionals_) {
      text << helpLine(positional.name, positional.help);
    }
  }
  text << "\nOptions:\n";
  for (const Option& option : options_) {
    std::string left = option.name == "help" ? "-h, --help" : "--" + option.name;
    if (option.takesValue) left += " " + option.valueName;
    std::string help = option.help;
    if (option.defaultValue) help += " (default: " + *option.defaultValue + ")";
    text << helpLine(left, help);
  }
  text << "\nCore parameters: --Group/Name value (see --params), e.g. --"
       << Parameters::kRtabmapDetectionRate() << " 2\n";
  for (const std::string& note : notes_) text << "\n" << note << "\n";
  return text.str();
}

void printParameters(std::ostream& out, bool asJson, const ParametersMap& current) {
  if (!asJson) {
    Parameters::print(out, current);
    return;
  }
  nlohmann::json list = nlohmann::json::array();
  for (const ParameterInfo& parameter : Parameters::all()) {
    nlohmann::json entry = parameterToJson(parameter);
    if (const auto it = current.find(parameter.key); it != current.end()) entry["value"] = it->second;
    list.push_back(entry);
  }
  printJsonLine(list, out);
}

int runTool(const std::string& toolName, const std::function<int()>& body) {
  return runTool(toolName, body, std::cerr);
}

int runTool(const std::string& toolName, const std::function<int()>& body, std::ostream& err) {
  const LogLevel previousLevel = logLevel();
  setLogLevel(LogLevel::kWarning);
  setLogSink([&err, toolName](LogLevel level, const std::string& message) {
    err << toolName << ": " << logLevelName(level) << ": " << message << std::endl;
  });
  int exitCode = kExitFailure;
  try {
    exitCode = body();
  } catch (const UsageError& error) {
    err << toolName << ": error: " << error.what() << "\nRun '" << toolName
        << " --help' for usage.\n";
    exitCode = kExitUsage;
  } catch (const std::exception& error) {
    err << toolName << ": error: " << error.what() << "\n";
    exitCode = kExitFailure;
  } catch (...) {
    err << toolName << ": error: unexpected failure of unknown type\n";
    exitCode = kExitFailure;
  }
  // err may not outlive this call: go back to a sink on std::cerr (warnings and errors).
  setLogSink([](LogLevel level, const std::string& message) {
    if (level >= LogLevel::kWarning) std::cerr << "[" << logLevelName(level) << "] " << message << std::endl;
  });
  setLogLevel(previousLevel);
  return exitCode;
}

}  // namespace rtabmap::tools

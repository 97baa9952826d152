#pragma once
// The command-line framework shared by every rtabmap-* tool (DESIGN.md section 5).
//
// Every tool gets, without writing it: --help, --params (all core parameters with defaults and
// descriptions), --json (one JSON object as the last line of stdout, see Json.h), --config FILE
// (core parameters from an INI file), --verbose, and --Group/Name value core parameters checked
// against the registry. A tool declares its own flags, options and positionals, then parses:
//
//   int main(int argc, char** argv) {
//     return rtabmap::tools::runTool("rtabmap-info", [&] {
//       rtabmap::tools::CommandLine cli("rtabmap-info", "Prints what a database holds.");
//       cli.addPositional("database", "Path of the RTAB-Map database (.db).");
//       cli.addOption("max-nodes", "N", "Stop after N nodes.", "0");
//       if (auto exitCode = cli.parse(argc, argv)) return *exitCode;
//       ... cli.positional("database"), cli.optionInt("max-nodes"), cli.parameters() ...
//       if (cli.json()) rtabmap::tools::printJsonLine(summary);
//       return 0;
//     });
//   }
//
// Exit codes: 0 success, 1 the run failed (runTool), 2 the command line was wrong.
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap::tools {

inline constexpr int kExitSuccess = 0;
inline constexpr int kExitFailure = 1;  // the run itself failed: bad data, I/O, ...
inline constexpr int kExitUsage = 2;    // the command line was wrong: nothing was run

// A command line the user got wrong: unknown option, missing value, a number that is not one.
// runTool() and CommandLine::parse() turn it into exit code 2 and a pointer to --help.
class UsageError : public Error {
 public:
  using Error::Error;
};

class CommandLine {
 public:
  // toolName is what the user types ("rtabmap-info"); summary is one or two sentences for --help.
  CommandLine(std::string toolName, std::string summary);

  // ---- Declarations, before parse(). Names are given without dashes: "output" -> --output.
  // A switch without a value, false unless given.
  CommandLine& addFlag(const std::string& name, const std::string& help);
  // An option taking one value (--name VALUE or --name=VALUE); the last occurrence wins.
  // valueName is shown in --help ("FILE", "N"); defaultValue, if any, is used when absent.
  CommandLine& addOption(const std::string& name, const std::string& valueName,
                         const std::string& help,
                         std::optional<std::string> defaultValue = std::nullopt);
  // One positional argument, in declaration order. Required ones must come before optional ones.
  CommandLine& addPositional(const std::string& name, const std::string& help,
                             bool required = true);
  // All remaining positional arguments (at least minCount of them); declared last.
  CommandLine& addPositionalList(const std::string& name, const std::string& help,
                                 std::size_t minCount = 0);
  // A paragraph printed at the end of --help, e.g. an example command line.
  CommandLine& addNote(const std::string& text);

  // ---- Parsing. argv[0] is the program path and is skipped.
  // Returns std::nullopt when the tool should run. Otherwise returns the exit code the tool must
  // return at once: 0 after --help / --params (printed to out), 2 after a usage or parameter
  // error (printed to err as "<tool>: error: ..." plus a hint to run --help).
  std::optional<int> parse(int argc, const char* const argv[], std::ostream& out,
                           std::ostream& err);
  std::optional<int> parse(int argc, char** argv);  // out = std::cout, err = std::cerr
  // Same on the arguments after argv[0], throwing UsageError / ParameterError instead of printing.
  // Returns true if --help or --params was given (nothing else is checked then).
  bool parseOrThrow(const std::vector<std::string>& args);

  // ---- Results, after parsing.
  bool flag(const std::string& name) const;
  // True if the option was given on the command line or has a default.
  bool has(const std::string& name) const;
  // The option's value (or its default); UsageError if neither.
  std::string option(const std::string& name) const;
  // The option's value converted; UsageError naming the option if the text is not such a number.
  int optionInt(const std::string& name) const;
  double optionDouble(const std::string& name) const;
  // A single positional; "" if it is optional and was not given.
  std::string positional(const std::string& name) const;
  // The values of addPositionalList().
  std::vector<std::string> positionalList(const std::string& name) const;
  // --json was given: print one JSON object as the last stdout line, keep stderr quiet.
  bool json() const { return json_; }
  bool helpRequested() const { return help_; }
  bool paramsRequested() const { return params_; }
  // Core parameters the user set: those of --config FILE, overridden by --Group/Name value
  // arguments. All keys and values are valid (checked against the registry during parsing).
  const ParametersMap& parameters() const { return parameters_; }

  std::string helpText() const;
  const std::string& toolName() const { return toolName_; }

 private:
  struct Option {
    std::string name, valueName, help;
    bool takesValue = false;
    std::optional<std::string> defaultValue;
    std::optional<std::string> value;  // set by parsing (flags: "1")
  };
  struct Positional {
    std::string name, help;
    bool required = true;
    bool list = false;
    std::size_t minCount = 0;
    std::vector<std::string> values;
  };

  void declareOption(Option option);
  Option* findOption(const std::string& name);
  const Option& declaredOption(const std::string& name) const;
  const Positional& declaredPositional(const std::string& name) const;
  // Reads the option at args[index] (and its value); returns the index of the last argument used.
  std::size_t takeOption(const std::vector<std::string>& args, std::size_t index);
  void assignPositionals(const std::vector<std::string>& values);
  std::string synopsis() const;

  std::string toolName_;
  std::string summary_;
  std::vector<Option> options_;
  std::vector<Positional> positionals_;
  std::vector<std::string> notes_;
  ParametersMap parameters_;
  bool json_ = false;
  bool help_ = false;
  bool params_ = false;
};

// Prints every core parameter (key = default, accepted values, description) to out: what
// --params shows. Values set in `current` are shown with their default. With asJson, prints
// instead one JSON array line of objects {key, type, default, expected, description, and
// min/above, max/below, choices [{value, meaning}], value (if set) when they apply}.
void printParameters(std::ostream& out, bool asJson, const ParametersMap& current = {});

// Runs a tool body and makes failures readable: UsageError prints "<tool>: error: <message>"
// and a hint to run --help, and returns 2; any other exception (rtabmap::Error, std::exception)
// prints "<tool>: error: <message>" and returns 1. Otherwise returns what body returned.
// Also routes core log messages to err, prefixed by the tool name.
int runTool(const std::string& toolName, const std::function<int()>& body);
int runTool(const std::string& toolName, const std::function<int()>& body, std::ostream& err);

}  // namespace rtabmap::tools

// The command-line framework of the tools, exercised through its parsing functions (nothing
// here exits the test process).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "common/CommandLine.h"
#include "common/Json.h"
#include "common/TestData.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap::tools {
namespace {

CommandLine exampleTool() {
  CommandLine cli("rtabmap-example", "Does example things to a database.");
  cli.addPositional("database", "Path of the RTAB-Map database.")
      .addPositional("output", "Where to write the result.", false)
      .addFlag("fast", "Skip the slow checks.")
      .addOption("max-nodes", "N", "Stop after N nodes.", "0")
      .addOption("label", "TEXT", "Label of the run.")
      .addNote("Example: rtabmap-example --fast map.db");
  return cli;
}

struct ParseOutcome {
  std::optional<int> exitCode;
  std::string out, err;
};

ParseOutcome parse(CommandLine& cli, std::vector<std::string> args) {
  args.insert(args.begin(), "rtabmap-example");
  std::vector<const char*> argv;
  for (const std::string& arg : args) argv.push_back(arg.c_str());
  std::ostringstream out, err;
  ParseOutcome outcome;
  outcome.exitCode = cli.parse(static_cast<int>(argv.size()), argv.data(), out, err);
  outcome.out = out.str();
  outcome.err = err.str();
  return outcome;
}

TEST(CommandLine, MixedToolArgumentsAndCoreParameters) {
  CommandLine cli = exampleTool();
  const ParseOutcome outcome =
      parse(cli, {"--Rtabmap/DetectionRate", "2", "map.db", "--fast", "--max-nodes=30",
                  "--Kp/MaxFeatures", "-1", "out dir", "--label", "-x-", "--json"});
  ASSERT_FALSE(outcome.exitCode) << outcome.err;
  EXPECT_EQ(cli.positional("database"), "map.db");
  EXPECT_EQ(cli.positional("output"), "out dir");
  EXPECT_TRUE(cli.flag("fast"));
  EXPECT_TRUE(cli.json());
  EXPECT_EQ(cli.optionInt("max-nodes"), 30);
  EXPECT_EQ(cli.option("label"), "-x-");
  EXPECT_EQ(cli.parameters(), (ParametersMap{{"Rtabmap/DetectionRate", "2"}, {"Kp/MaxFeatures", "-1"}}));
  EXPECT_TRUE(outcome.out.empty());
  EXPECT_TRUE(outcome.err.empty());
}

TEST(CommandLine, DefaultsAndAbsentValues) {
  CommandLine cli = exampleTool();
  ASSERT_FALSE(parse(cli, {"map.db"}).exitCode);
  EXPECT_FALSE(cli.flag("fast"));
  EXPECT_FALSE(cli.json());
  EXPECT_EQ(cli.optionInt("max-nodes"), 0);
  EXPECT_TRUE(cli.has("max-nodes"));
  EXPECT_FALSE(cli.has("label"));
  EXPECT_THROW(cli.option("label"), UsageError);
  EXPECT_EQ(cli.positional("output"), "");
  EXPECT_TRUE(cli.parameters().empty());
}

TEST(CommandLine, HelpListsSynopsisArgumentsOptionsAndCoreParameters) {
  CommandLine cli = exampleTool();
  const ParseOutcome outcome = parse(cli, {"--bogus", "--help"});  // help wins over errors
  ASSERT_EQ(outcome.exitCode, std::optional<int>(kExitSuccess));
  const std::string& help = outcome.out;
  for (const char* part :
       {"Usage: rtabmap-example [options] [--Group/Name value ...] database [output]",
        "Does example things", "database", "Path of the RTAB-Map database.", "--fast",
        "Skip the slow checks.", "--max-nodes N", "(default: 0)", "--label TEXT", "-h, --help",
        "--params", "--json", "--config FILE", "Core parameters: --Group/Name value (see --params)",
        "Example: rtabmap-example --fast map.db"}) {
    EXPECT_NE(help.find(part), std::string::npos) << "missing \"" << part << "\" in:\n" << help;
  }
  EXPECT_EQ(help, cli.helpText());
}

TEST(CommandLine, ParamsPrintsEveryKeyAndExitsZeroWithoutToolArguments) {
  CommandLine cli = exampleTool();
  const ParseOutcome outcome = parse(cli, {"--params", "--Grid/CellSize", "0.1"});
  ASSERT_EQ(outcome.exitCode, std::optional<int>(kExitSuccess)) << outcome.err;
  for (const ParameterInfo& parameter : Parameters::all()) {
    EXPECT_NE(outcome.out.find("\n" + parameter.key + " = "), std::string::npos) << parameter.key;
  }
  EXPECT_NE(outcome.out.find("Grid/CellSize = 0.1   (default 0.05"), std::string::npos);
}

TEST(CommandLine, ParamsWithJsonPrintsOneMachineReadableLine) {
  CommandLine cli = exampleTool();
  const ParseOutcome outcome = parse(cli, {"--params", "--json"});
  ASSERT_EQ(outcome.exitCode, std::optional<int>(kExitSuccess));
  ASSERT_EQ(std::count(outcome.out.begin(), outcome.out.end(), '\n'), 1) << outcome.out.substr(0, 200);
  const nlohmann::json list = nlohmann::json::parse(outcome.out);
  ASSERT_EQ(list.size(), Parameters::all().size());
  const auto odom = std::find_if(list.begin(), list.end(),
                                 [](const nlohmann::json& entry) { return entry["key"] == "Odom/Strategy"; });
  ASSERT_NE(odom, list.end());
  EXPECT_EQ((*odom)["default"], "0");
  EXPECT_EQ((*odom)["choices"][1]["meaning"], "Frame-to-Frame (F2F)");
}

TEST(CommandLine, BadCoreParameterPrintsTheErrorAndExitsTwo) {
  CommandLine cli = exampleTool();
  ParseOutcome outcome = parse(cli, {"map.db", "--Rtabmap/DetectionRat", "2"});
  EXPECT_EQ(outcome.exitCode, std::optional<int>(kExitUsage));
  EXPECT_NE(outcome.err.find("rtabmap-example: error: "), std::string::npos) << outcome.err;
  EXPECT_NE(outcome.err.find("Rtabmap/DetectionRate"), std::string::npos) << outcome.err;
  EXPECT_NE(outcome.err.find("--help"), std::string::npos) << outcome.err;

  CommandLine other = exampleTool();
  outcome = parse(other, {"map.db", "--Kp/MaxFeatures", "lots"});
  EXPECT_EQ(outcome.exitCode, std::optional<int>(kExitUsage));
  EXPECT_NE(outcome.err.find("\"lots\""), std::string::npos) << outcome.err;
}

TEST(CommandLine, UsageErrorsExitTwoWithAClearMessage) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{}, "missing argument database"},
      {{"a.db", "b", "c"}, "unexpected argument \"c\""},
      {{"a.db", "--fsat"}, "unknown option --fsat (did you mean --fast?)"},
      {{"a.db", "-q"}, "unknown option -q"},
      {{"a.db", "--label"}, "option --label needs a value"},
      {{"a.db", "--fast=1"}, "option --fast takes no value"},
      {{"a.db", "--Kp/MaxFeatures"}, "--Kp/MaxFeatures needs a value"},
  };
  for (const auto& [args, expected] : cases) {
    CommandLine cli = exampleTool();
    const ParseOutcome outcome = parse(cli, args);
    EXPECT_EQ(outcome.exitCode, std::optional<int>(kExitUsage)) << expected;
    EXPECT_NE(outcome.err.find(expected), std::string::npos) << "expected \"" << expected
                                                             << "\" in: " << outcome.err;
    EXPECT_TRUE(outcome.out.empty());
  }
}

TEST(CommandLine, TypedOptionGettersNameTheOptionOnBadText) {
  CommandLine cli = exampleTool();
  ASSERT_FALSE(parse(cli, {"a.db", "--max-nodes", "12x"}).exitCode);
  try {
    cli.optionInt("max-nodes");
    FAIL() << "expected a UsageError";
  } catch (const UsageError& error) {
    EXPECT_NE(std::string(error.what()).find("--max-nodes expects a whole number, got \"12x\""),
              std::string::npos)
        << error.what();
  }
  EXPECT_THROW(cli.optionDouble("max-nodes"), UsageError);
}

TEST(CommandLine, ConfigFileParametersAreOverriddenByArguments) {
  test::TempDir dir;
  const std::string ini = dir.file("robot.ini");
  std::ofstream(ini) << "[Core]\nMem/STMSize = 20\nKp/MaxFeatures = 300\n";
  CommandLine cli = exampleTool();
  const ParseOutcome outcome = parse(cli, {"a.db", "--config", ini, "--Kp/MaxFeatures", "100"});
  ASSERT_FALSE(outcome.exitCode) << outcome.err;
  EXPECT_EQ(cli.parameters(), (ParametersMap{{"Mem/STMSize", "20"}, {"Kp/MaxFeatures", "100"}}));

  std::ofstream(ini) << "[Core]\nMem/STMSiz = 20\n";
  CommandLine bad = exampleTool();
  const ParseOutcome failed = parse(bad, {"a.db", "--config", ini});
  EXPECT_EQ(failed.exitCode, std::optional<int>(kExitUsage));
  EXPECT_NE(failed.err.find(ini + ":2:"), std::string::npos) << failed.err;
  EXPECT_NE(failed.err.find("Mem/STMSize"), std::string::npos) << failed.err;
}

TEST(CommandLine, PositionalListTakesTheRestAfterDoubleDash) {
  CommandLine cli("rtabmap-merge", "Merges databases.");
  cli.addPositional("output", "Merged database.").addPositionalList("inputs", "Databases.", 2);
  std::ostringstream out, err;
  const char* argv[] = {"rtabmap-merge", "out.db", "a.db", "--", "--odd-name.db"};
  ASSERT_FALSE(cli.parse(5, argv, out, err)) << err.str();
  EXPECT_EQ(cli.positional("output"), "out.db");
  EXPECT_EQ(cli.positionalList("inputs"), (std::vector<std::string>{"a.db", "--odd-name.db"}));
  CommandLine few("rtabmap-merge", "Merges databases.");
  few.addPositional("output", "Merged database.").addPositionalList("inputs", "Databases.", 2);
  EXPECT_THROW(few.parseOrThrow({"out.db", "a.db"}), UsageError);
  EXPECT_NE(few.helpText().find("output inputs ..."), std::string::npos) << few.helpText();
}

TEST(CommandLine, DeclarationMistakesAreProgrammingErrors) {
  CommandLine cli("rtabmap-x", "X.");
  EXPECT_THROW(cli.addFlag("json", "again"), std::logic_error);
  EXPECT_THROW(cli.addFlag("--dashed", "no"), std::logic_error);
  cli.addPositional("optional", "o", false);
  EXPECT_THROW(cli.addPositional("required", "r", true), std::logic_error);
  EXPECT_THROW(cli.flag("undeclared"), std::logic_error);
}

TEST(CommandLine, VerboseAndDebugSetTheCoreLogLevel) {
  const LogLevel before = logLevel();
  for (const auto& [flag, level] : {std::pair<std::string, LogLevel>{"--verbose", LogLevel::kInfo},
                                    {"--debug", LogLevel::kDebug},
                                    {"--verbose --debug", LogLevel::kDebug}}) {
    setLogLevel(LogLevel::kWarning);
    CommandLine cli = exampleTool();
    std::vector<std::string> args{"map.db"};
    std::istringstream words(flag);
    for (std::string w; words >> w;) args.push_back(w);
    EXPECT_FALSE(parse(cli, args).exitCode.has_value()) << flag;
    EXPECT_EQ(logLevel(), level) << flag;
  }
  setLogLevel(LogLevel::kWarning);
  CommandLine quiet = exampleTool();
  EXPECT_FALSE(parse(quiet, {"map.db"}).exitCode.has_value());
  EXPECT_EQ(logLevel(), LogLevel::kWarning);
  setLogLevel(before);
}

TEST(RunTool, ReturnsTheBodysCodeAndTurnsExceptionsIntoOneLineErrors) {
  std::ostringstream err;
  EXPECT_EQ(runTool("rtabmap-x", [] { return 0; }, err), kExitSuccess);
  EXPECT_EQ(runTool("rtabmap-x", [] { return 3; }, err), 3);
  EXPECT_TRUE(err.str().empty());

  EXPECT_EQ(runTool("rtabmap-x", []() -> int { throw DatabaseError("cannot open \"a.db\": no such file"); }, err),
            kExitFailure);
  EXPECT_EQ(err.str(), "rtabmap-x: error: cannot open \"a.db\": no such file\n");

  err.str("");
  EXPECT_EQ(runTool("rtabmap-x", []() -> int { throw std::runtime_error("disk full"); }, err),
            kExitFailure);
  EXPECT_EQ(err.str(), "rtabmap-x: error: disk full\n");

  err.str("");
  EXPECT_EQ(runTool("rtabmap-x", []() -> int { throw UsageError("--max-nodes expects a number"); }, err),
            kExitUsage);
  EXPECT_NE(err.str().find("rtabmap-x: error: --max-nodes expects a number\n"), std::string::npos);
  EXPECT_NE(err.str().find("rtabmap-x --help"), std::string::npos);

  err.str("");
  EXPECT_EQ(runTool("rtabmap-x", []() -> int { throw 42; }, err), kExitFailure);
  EXPECT_NE(err.str().find("rtabmap-x: error:"), std::string::npos);
}

TEST(RunTool, RoutesCoreWarningsToStderrWithTheToolName) {
  std::ostringstream err;
  runTool("rtabmap-x", [] {
    RTABMAP_WARN("node " << 7 << " has no words");
    RTABMAP_INFO("quiet unless --verbose");
    return 0;
  }, err);
  EXPECT_EQ(err.str(), "rtabmap-x: WARN: node 7 has no words\n");
}

}  // namespace
}  // namespace rtabmap::tools

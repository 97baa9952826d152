// "--Group/Name value" arguments mixed with a tool's own arguments.
#include <gtest/gtest.h>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
namespace {

std::string argumentError(const std::vector<std::string>& args) {
  try {
    Parameters::parseArguments(args);
  } catch (const ParameterError& error) {
    return error.what();
  }
  return "";
}

TEST(ParameterArguments, SeparatesParametersFromToolArguments) {
  const ParsedArguments parsed = Parameters::parseArguments(std::vector<std::string>{
      "--json", "--Rtabmap/DetectionRate", "2", "input.db", "--output", "/tmp/out/x",
      "--Kp/MaxFeatures=-1", "--Mem/IncrementalMemory", "false", "-v", "--Kp/RoiRatios",
      "0 0 0.1 0.1"});
  EXPECT_EQ(parsed.parameters, (ParametersMap{{"Rtabmap/DetectionRate", "2"},
                                              {"Kp/MaxFeatures", "-1"},
                                              {"Mem/IncrementalMemory", "false"},
                                              {"Kp/RoiRatios", "0 0 0.1 0.1"}}));
  EXPECT_EQ(parsed.remaining,
            (std::vector<std::string>{"--json", "input.db", "--output", "/tmp/out/x", "-v"}));
}

TEST(ParameterArguments, NegativeNumbersAreValuesAndTheLastOccurrenceWins) {
  const ParsedArguments parsed = Parameters::parseArguments(
      std::vector<std::string>{"--StereoBM/Disp12MaxDiff", "-5", "--Mem/STMSize", "5",
                               "--Mem/STMSize", "7"});
  EXPECT_EQ(parsed.parameters.at("StereoBM/Disp12MaxDiff"), "-5");
  EXPECT_EQ(parsed.parameters.at("Mem/STMSize"), "7");
  EXPECT_TRUE(parsed.remaining.empty());
}

TEST(ParameterArguments, DoubleDashStopsTheScan) {
  const ParsedArguments parsed = Parameters::parseArguments(
      std::vector<std::string>{"a", "--", "--Mem/STMSize", "x"});
  EXPECT_TRUE(parsed.parameters.empty());
  EXPECT_EQ(parsed.remaining, (std::vector<std::string>{"a", "--", "--Mem/STMSize", "x"}));
}

TEST(ParameterArguments, MissingValueIsAnError) {
  std::string error = argumentError({"db", "--Kp/MaxFeatures"});
  EXPECT_NE(error.find("--Kp/MaxFeatures needs a value"), std::string::npos) << error;
  EXPECT_NE(error.find("an int"), std::string::npos) << error;
  error = argumentError({"--Kp/MaxFeatures", "--json"});
  EXPECT_NE(error.find("needs a value"), std::string::npos) << error;
}

TEST(ParameterArguments, InvalidOrUnknownParametersAreErrors) {
  std::string error = argumentError({"--Kp/MaxFeatures", "many"});
  EXPECT_NE(error.find("Kp/MaxFeatures"), std::string::npos) << error;
  EXPECT_NE(error.find("\"many\""), std::string::npos) << error;
  error = argumentError({"--Rtabmap/DetectionRat", "1"});
  EXPECT_NE(error.find("Rtabmap/DetectionRat\""), std::string::npos) << error;
  EXPECT_NE(error.find("--Rtabmap/DetectionRate?"), std::string::npos) << error;
}

TEST(ParameterArguments, ArgcArgvFormSkipsTheProgramName) {
  const char* argv[] = {"rtabmap-info", "--Mem/STMSize", "3", "db"};
  const ParsedArguments parsed = Parameters::parseArguments(4, argv);
  EXPECT_EQ(parsed.parameters, (ParametersMap{{"Mem/STMSize", "3"}}));
  EXPECT_EQ(parsed.remaining, (std::vector<std::string>{"db"}));
}

}  // namespace
}  // namespace rtabmap

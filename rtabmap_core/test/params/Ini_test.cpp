// INI files in the original config.ini layout.
#include <gtest/gtest.h>

#include <sstream>

#include "common/TestData.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
namespace {

std::string iniError(const std::string& text, const std::string& source = "robot.ini") {
  try {
    Parameters::parseIni(text, source);
  } catch (const ParameterError& error) {
    return error.what();
  }
  return "";
}

// A number other than the default that the declaration accepts: default + 1, or when that
// is above the maximum, halfway to the maximum (or to the minimum if the default is the max).
std::string changedNumber(const ParameterInfo& parameter) {
  const ParameterLimits& limits = parameter.limits;
  const double original = std::stod(parameter.defaultValue);
  double number = original + 1;
  if (limits.max && number > *limits.max) {
    const double bound = original < *limits.max ? *limits.max : limits.min.value_or(original - 2);
    number = (original + bound) / 2;
  }
  if (parameter.type == ParameterType::kInt) return std::to_string(static_cast<int>(number));
  std::ostringstream text;
  text.precision(9);
  text << number;
  return text.str();
}

// Every declared parameter set to a value different from its default.
ParametersMap nonDefaultValues() {
  ParametersMap values;
  for (const ParameterInfo& parameter : Parameters::all()) {
    const ParameterLimits& limits = parameter.limits;
    if (!limits.notImplemented.empty()) continue;  // only its default is accepted
    std::string value;
    if (!limits.choices.empty()) {
      for (const ParameterChoice& choice : limits.choices) {
        if (choice.value != parameter.defaultValue) value = choice.value;
      }
      if (value.empty()) continue;  // a single allowed value cannot change
    } else if (parameter.type == ParameterType::kBool) {
      value = parameter.defaultValue == "true" ? "false" : "true";
    } else if (parameter.type == ParameterType::kString) {
      value = limits.numberListSize == 4 ? "0.1 0.2 0.05 0.25"
              : limits.numberListSize == 0 ? "0.5 0.25 0.125"
                                            : "  path with spaces/and \"quotes\" ;# and = signs\n";
    } else {
      value = changedNumber(parameter);
    }
    values[parameter.key] = value;
  }
  return values;
}

TEST(ParameterIni, WriteThenReadRoundTripsAFullMapOfNonDefaultValues) {
  const ParametersMap written = nonDefaultValues();
  ASSERT_GT(written.size(), Parameters::all().size() * 3 / 4);
  for (const auto& [key, value] : written) EXPECT_NE(value, Parameters::defaults().at(key)) << key;
  Parameters::validate(written);
  test::TempDir dir;
  const std::string path = dir.file("config.ini");
  Parameters::writeIni(path, written);
  const ParametersMap read = Parameters::readIni(path);
  EXPECT_EQ(read, written);
  EXPECT_EQ(read.at("Db/TargetVersion"),
            "  path with spaces/and \"quotes\" ;# and = signs\n");
}

TEST(ParameterIni, WrittenFileIsTheOriginalLayoutWithDescriptions) {
  const std::string text = Parameters::formatIni({{"Rtabmap/DetectionRate", "2"}});
  EXPECT_NE(text.find("[Core]\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nRtabmap/DetectionRate = 2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("# Rate (Hz)"), std::string::npos) << text;
  EXPECT_THROW(Parameters::formatIni({{"Rtabmap/Nope", "2"}}), ParameterError);
}

TEST(ParameterIni, ReadsCommentsSectionsQuotesAndTheOriginalsBackslashKeys) {
  const std::string text =
      "; written by hand\n"
      "[Core]\n"
      "# a comment\n"
      "Version = 0.21.4\n"
      "Rtabmap\\DetectionRate=2\n"
      "  Kp/MaxFeatures   =   400  \r\n"
      "Db/TargetVersion = \"  /tmp/a \\\"b\\\"\\n\"\n"
      "Rtabmap/LoopThr =0.2\n"
      "Rtabmap/LoopThr = 0.3\n"
      "[Gui]\n"
      "anything goes here = 1\n"
      "not even an equal sign\n"
      "[core]\n"
      "Mem/STMSize = 20\n";
  const ParametersMap read = Parameters::parseIni(text, "hand.ini");
  const ParametersMap expected = {{"Rtabmap/DetectionRate", "2"},
                                  {"Kp/MaxFeatures", "400"},
                                  {"Db/TargetVersion", "  /tmp/a \"b\"\n"},
                                  {"Rtabmap/LoopThr", "0.3"},
                                  {"Mem/STMSize", "20"}};
  EXPECT_EQ(read, expected);
}

TEST(ParameterIni, MalformedLineErrorNamesFileAndLine) {
  const std::string error = iniError("[Core]\n# ok\nKp/MaxFeatures 400\n");
  EXPECT_NE(error.find("robot.ini:3:"), std::string::npos) << error;
  EXPECT_NE(error.find("Kp/MaxFeatures 400"), std::string::npos) << error;
  EXPECT_NE(iniError("[Core]\n = 3\n").find("robot.ini:2:"), std::string::npos);
  EXPECT_NE(iniError("[Core\nKp/MaxFeatures = 1\n").find("robot.ini:1: malformed section"),
            std::string::npos);
  EXPECT_NE(iniError("Db/TargetVersion = \"open\n").find("robot.ini:1: unterminated"),
            std::string::npos);
}

TEST(ParameterIni, UnknownKeyErrorNamesFileLineKeyAndClosestKey) {
  const std::string error = iniError("[Core]\nRtabmap/DetectionRate = 1\n\nRtabmap/DetectionRat = 2\n");
  EXPECT_NE(error.find("robot.ini:4:"), std::string::npos) << error;
  EXPECT_NE(error.find("\"Rtabmap/DetectionRat\""), std::string::npos) << error;
  EXPECT_NE(error.find("\"Rtabmap/DetectionRate\""), std::string::npos) << error;
}

TEST(ParameterIni, InvalidValueErrorNamesFileLineKeyAndValue) {
  const std::string error = iniError("[Core]\nGrid/CellSize = -1\n");
  EXPECT_NE(error.find("robot.ini:2:"), std::string::npos) << error;
  EXPECT_NE(error.find("Grid/CellSize"), std::string::npos) << error;
  EXPECT_NE(error.find("\"-1\""), std::string::npos) << error;
}

TEST(ParameterIni, MissingFileIsAClearError) {
  try {
    Parameters::readIni("/nonexistent/dir/rtabmap.ini");
    FAIL() << "expected a ParameterError";
  } catch (const ParameterError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/dir/rtabmap.ini"), std::string::npos);
  }
  EXPECT_THROW(Parameters::writeIni("/nonexistent/dir/out.ini", {}), ParameterError);
}

}  // namespace
}  // namespace rtabmap

// Errors a robotics user sees for a wrong key or value, and typed access.
#include <gtest/gtest.h>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/params/ClosestMatch.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
namespace {

// The message of the ParameterError thrown by validate(key, value), "" if none.
std::string validationError(const std::string& key, const std::string& value) {
  try {
    Parameters::validate(key, value);
  } catch (const ParameterError& error) {
    return error.what();
  }
  return "";
}

void expectContains(const std::string& text, const std::vector<std::string>& parts) {
  for (const std::string& part : parts) {
    EXPECT_NE(text.find(part), std::string::npos) << "\"" << part << "\" missing in: " << text;
  }
}

TEST(ParameterValidation, UnknownKeyNamesTheKeyAndTheClosestValidKey) {
  expectContains(validationError("Rtabmap/DetectionRat", "1"),
                 {"unknown parameter", "\"Rtabmap/DetectionRat\"", "\"Rtabmap/DetectionRate\""});
  expectContains(validationError("Vis/MinInlier", "10"), {"Vis/MinInlier\"", "\"Vis/MinInliers\""});
  // Case mistakes are the nearest of all.
  expectContains(validationError("icp/voxelsize", "0.1"), {"\"Icp/VoxelSize\""});
  // The right name in the wrong group, or without a group.
  expectContains(validationError("Mem/DetectionRate", "1"), {"\"Rtabmap/DetectionRate\""});
  expectContains(validationError("DetectionRate", "1"),
                 {"Group/Name", "\"Rtabmap/DetectionRate\""});
}

TEST(ParameterValidation, WrongTypeNamesKeyValueAndExpectedType) {
  expectContains(validationError("Kp/MaxFeatures", "abc"),
                 {"Kp/MaxFeatures", "\"abc\"", "not a number", "an int"});
  expectContains(validationError("Kp/MaxFeatures", "2.5"),
                 {"Kp/MaxFeatures", "\"2.5\"", "not a whole number", "an int"});
  expectContains(validationError("Mem/IncrementalMemory", "maybe"),
                 {"Mem/IncrementalMemory", "\"maybe\"", "not a bool", "true, false, 1 or 0"});
  expectContains(validationError("Rtabmap/LoopThr", "0,11"),
                 {"Rtabmap/LoopThr", "\"0,11\"", "not a number", "a float"});
  expectContains(validationError("Optimizer/Epsilon", "1e-6x"), {"\"1e-6x\"", "a double"});
  expectContains(validationError("Kp/MaxFeatures", "99999999999"), {"too large for an int"});
  expectContains(validationError("Kp/RoiRatios", "0 0 zero 0"), {"\"zero\" is not a number"});
}

TEST(ParameterValidation, OutOfRangeNamesKeyValueAndRange) {
  expectContains(validationError("Mem/RehearsalSimilarity", "1.5"),
                 {"Mem/RehearsalSimilarity", "\"1.5\"", "out of range", "[0, 1]"});
  expectContains(validationError("Grid/CellSize", "0"),
                 {"Grid/CellSize", "\"0\"", "out of range", "> 0", "default \"0.05\""});
  expectContains(validationError("Mem/STMSize", "-1"), {"Mem/STMSize", "\"-1\"", ">= 0"});
  expectContains(validationError("Odom/Strategy", "5"),
                 {"Odom/Strategy", "\"5\"", "not an allowed value", "0 (Frame-to-Map (F2M))",
                  "1 (Frame-to-Frame (F2F))"});
  expectContains(validationError("Kp/RoiRatios", "0 0 0"), {"3 numbers instead of 4"});
  expectContains(validationError("Kp/RoiRatios", "0 0 0 2"), {"2 is out of range", "[0, 1]"});
  expectContains(validationError("Mem/ImageCompressionFormat", ".bmp"),
                 {"\".bmp\"", "\".jpg\"", "\".png\""});
  expectContains(validationError("Rtabmap/DetectionRate", "1e39"), {"too large for a float"});
}

TEST(ParameterValidation, NonFiniteNumbersAreRejected) {
  for (const char* value : {"nan", "NaN", "inf", "-inf", "infinity"}) {
    EXPECT_FALSE(Parameters::isValid("Rtabmap/LoopThr", value)) << value;
    EXPECT_FALSE(Parameters::isValid("Optimizer/Epsilon", value)) << value;
  }
}

TEST(ParameterValidation, AcceptsTheUsualSpellingsOfValidValues) {
  for (const char* value : {"true", "false", "TRUE", "False", "1", "0"}) {
    EXPECT_TRUE(Parameters::isValid("Mem/IncrementalMemory", value)) << value;
  }
  for (const char* value : {"yes", "on", "2", "", " true"}) {
    EXPECT_FALSE(Parameters::isValid("Mem/IncrementalMemory", value)) << "\"" << value << "\"";
  }
  for (const char* value : {"0.5", ".5", "5e-1", "+0.5", "1", "0"}) {
    EXPECT_TRUE(Parameters::isValid("Mem/RehearsalSimilarity", value)) << value;
  }
  EXPECT_TRUE(Parameters::isValid("Odom/Strategy", "+1"));
  EXPECT_TRUE(Parameters::isValid("Optimizer/Epsilon", "1e-400"));  // underflows to 0, fine
  EXPECT_FALSE(Parameters::isValid("Optimizer/Epsilon", "1e400"));   // overflows to inf
  EXPECT_FALSE(Parameters::isValid("Kp/MaxFeatures", " 500"));  // numbers must parse completely
  EXPECT_FALSE(Parameters::isValid("Kp/MaxFeatures", "500 "));
  EXPECT_FALSE(Parameters::isValid("Kp/MaxFeatures", ""));
  EXPECT_TRUE(Parameters::isValid("Db/TargetVersion", "/tmp/with space/é"));
}

TEST(ParameterValidation, WholeMapErrorListsEveryBadEntry) {
  const ParametersMap bad = {{"Kp/MaxFeatures", "x"}, {"Grid/CelSize", "0.1"}, {"Vis/MinInliers", "15"}};
  try {
    Parameters::validate(bad);
    FAIL() << "expected a ParameterError";
  } catch (const ParameterError& error) {
    expectContains(error.what(), {"2 invalid parameters", "Kp/MaxFeatures", "\"Grid/CellSize\""});
    EXPECT_EQ(std::string(error.what()).find("Vis/MinInliers"), std::string::npos);
  }
  EXPECT_NO_THROW(Parameters::validate(ParametersMap{{"Vis/MinInliers", "15"}}));
}

TEST(ParameterAccess, ReadsTheMapValueElseTheDefault) {
  const ParametersMap parameters = {{"Kp/MaxFeatures", "400"},
                                    {"Rtabmap/LoopThr", "0.2"},
                                    {"RGBD/Enabled", "FALSE"},
                                    {"Optimizer/Epsilon", "1e-4"},
                                    {"Db/TargetVersion", "/tmp/maps"}};
  EXPECT_EQ(Parameters::getInt(parameters, "Kp/MaxFeatures"), 400);
  EXPECT_EQ(Parameters::getInt(parameters, "Vis/MinInliers"), 20);
  EXPECT_FLOAT_EQ(Parameters::getFloat(parameters, "Rtabmap/LoopThr"), 0.2f);
  EXPECT_DOUBLE_EQ(Parameters::getDouble(parameters, "Optimizer/Epsilon"), 1e-4);
  EXPECT_FALSE(Parameters::getBool(parameters, "RGBD/Enabled"));
  EXPECT_TRUE(Parameters::getBool(parameters, "Mem/IncrementalMemory"));
  EXPECT_EQ(Parameters::getString(parameters, "Db/TargetVersion"), "/tmp/maps");
  EXPECT_EQ(Parameters::getString(parameters, "Kp/MaxFeatures"), "400");
  // Numbers widen: an int parameter can be read as float or double.
  EXPECT_DOUBLE_EQ(Parameters::getDouble(parameters, "Kp/MaxFeatures"), 400.0);
  const std::vector<double> roi = Parameters::getNumberList({}, "Kp/RoiRatios");
  EXPECT_EQ(roi, std::vector<double>({0, 0, 0, 0}));
  EXPECT_EQ(Parameters::getNumberList({}, "Bayes/PredictionLC").size(), 18u);
}

TEST(ParameterAccess, RejectsUndeclaredKeysInvalidValuesAndTypeMismatches) {
  EXPECT_THROW(Parameters::getInt({}, "Kp/MaxFeature"), ParameterError);
  EXPECT_THROW(Parameters::getInt({{"Kp/MaxFeatures", "many"}}, "Kp/MaxFeatures"), ParameterError);
  try {
    Parameters::getInt({}, "Rtabmap/LoopThr");
    FAIL() << "getInt on a float parameter must throw";
  } catch (const ParameterError& error) {
    expectContains(error.what(), {"Rtabmap/LoopThr", "float", "getInt"});
  }
  EXPECT_THROW(Parameters::getBool({}, "Kp/MaxFeatures"), ParameterError);
  EXPECT_THROW(Parameters::getDouble({}, "RGBD/Enabled"), ParameterError);
  EXPECT_THROW(Parameters::getNumberList({}, "Kp/MaxFeatures"), ParameterError);
}

TEST(ParameterAccess, FilterByGroupKeepsOnlyThatGroup) {
  const ParametersMap parameters = {{"Icp/VoxelSize", "0.1"},
                                    {"Icp/Iterations", "10"},
                                    {"IcpX/Other", "1"},
                                    {"Grid/CellSize", "0.1"}};
  const ParametersMap icp = Parameters::filterByGroup(parameters, "Icp");
  EXPECT_EQ(icp, (ParametersMap{{"Icp/Iterations", "10"}, {"Icp/VoxelSize", "0.1"}}));
  const ParametersMap icpDefaults = Parameters::filterByGroup(Parameters::defaults(), "Icp");
  EXPECT_EQ(icpDefaults.at("Icp/Iterations"), "30");
  EXPECT_EQ(icpDefaults.count("Grid/CellSize"), 0u);
}

TEST(ParameterAccess, WithDefaultsOverridesOnlyTheGivenKeys) {
  const ParametersMap merged = Parameters::withDefaults({{"Mem/STMSize", "30"}});
  EXPECT_EQ(merged.size(), Parameters::all().size());
  EXPECT_EQ(merged.at("Mem/STMSize"), "30");
  EXPECT_EQ(merged.at("Kp/MaxFeatures"), "500");
  EXPECT_THROW(Parameters::withDefaults({{"Mem/STMSize", "-3"}}), ParameterError);
}

TEST(ClosestMatch, EditDistanceIgnoresCase) {
  EXPECT_EQ(editDistanceIgnoringCase("kitten", "sitting"), 3u);
  EXPECT_EQ(editDistanceIgnoringCase("Grid/3D", "grid/3d"), 0u);
  EXPECT_EQ(editDistanceIgnoringCase("", "abc"), 3u);
  EXPECT_EQ(closestMatch("--jsno", {"--help", "--json", "--params"}), "--json");
  EXPECT_EQ(closestMatch("x", {}), "");
}

}  // namespace
}  // namespace rtabmap

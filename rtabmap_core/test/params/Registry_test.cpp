// The declarations themselves: every default valid, keys unique and well formed, the defaults
// the foundation issue fixes, and generated constants in agreement with the registry.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
namespace {

TEST(ParameterRegistry, EveryDefaultValidatesAgainstItsOwnDeclaration) {
  ASSERT_GT(Parameters::all().size(), 250u);
  for (const ParameterInfo& parameter : Parameters::all()) {
    std::string why;
    EXPECT_TRUE(Parameters::isValid(parameter.key, parameter.defaultValue, &why))
        << parameter.key << ": " << why;
  }
}

TEST(ParameterRegistry, KeysAreUniqueSortedAndInGroupNameForm) {
  std::set<std::string> seen;
  std::string previous;
  for (const ParameterInfo& parameter : Parameters::all()) {
    EXPECT_TRUE(seen.insert(parameter.key).second) << "duplicate key " << parameter.key;
    EXPECT_LT(previous, parameter.key) << "registry not sorted at " << parameter.key;
    previous = parameter.key;
    EXPECT_EQ(parameter.key, parameter.group + "/" + parameter.name);
    ASSERT_FALSE(parameter.group.empty()) << parameter.key;
    ASSERT_FALSE(parameter.name.empty()) << parameter.key;
    EXPECT_EQ(parameter.key.find('/'), parameter.group.size()) << "one slash only: " << parameter.key;
    EXPECT_EQ(parameter.key.find_first_of(" \t=;\\"), std::string::npos) << parameter.key;
  }
}

TEST(ParameterRegistry, EveryParameterHasAOneLineDescription) {
  for (const ParameterInfo& parameter : Parameters::all()) {
    EXPECT_GE(parameter.description.size(), 10u) << parameter.key;
    EXPECT_EQ(parameter.description.find('\n'), std::string::npos) << parameter.key;
  }
}

TEST(ParameterRegistry, EnumerationDefaultsAreAmongTheirChoices) {
  for (const ParameterInfo& parameter : Parameters::all()) {
    if (parameter.limits.choices.empty()) continue;
    bool found = false;
    for (const ParameterChoice& choice : parameter.limits.choices) {
      found = found || choice.value == parameter.defaultValue;
      EXPECT_FALSE(choice.meaning.empty()) << parameter.key << " choice " << choice.value;
    }
    EXPECT_TRUE(found) << parameter.key << " default " << parameter.defaultValue;
  }
}

TEST(ParameterRegistry, TheIssuesRequiredDefaultsHoldExactly) {
  const ParametersMap required = {
      {"Rtabmap/DetectionRate", "1"},      {"Rtabmap/TimeThr", "0"},
      {"Rtabmap/MemoryThr", "0"},          {"Rtabmap/LoopThr", "0.11"},
      {"Rtabmap/MaxRetrieved", "2"},       {"Mem/STMSize", "10"},
      {"Mem/RehearsalSimilarity", "0.6"},  {"Mem/RecentWmRatio", "0.2"},
      {"Mem/IncrementalMemory", "true"},   {"Mem/InitWMWithAllNodes", "false"},
      {"Kp/MaxFeatures", "500"},           {"Kp/NndrRatio", "0.8"},
      {"Kp/BadSignRatio", "0.5"},          {"Kp/TfIdfLikelihoodUsed", "true"},
      {"Vis/MinInliers", "20"},            {"Vis/CorNNDR", "0.8"},
      {"Vis/MaxFeatures", "1000"},         {"Vis/CorGuessWinSize", "40"},
      {"Reg/Strategy", "0"},               {"Reg/Force3DoF", "false"},
      {"RGBD/OptimizeMaxError", "3"},      {"RGBD/ProximityMaxGraphDepth", "50"},
      {"RGBD/ProximityBySpace", "true"},   {"RGBD/NeighborLinkRefining", "false"},
      {"RGBD/LinearUpdate", "0.1"},        {"RGBD/AngularUpdate", "0.1"},
      {"Odom/Strategy", "0"},              {"Odom/KeyFrameThr", "0.3"},
      {"OdomF2M/MaxSize", "2000"},         {"Grid/CellSize", "0.05"},
      {"Grid/RangeMax", "5"},              {"Grid/RayTracing", "false"},
      {"Optimizer/Iterations", "20"},      {"Icp/VoxelSize", "0.05"},
      {"Icp/Iterations", "30"},            {"Icp/CorrespondenceRatio", "0.1"},
  };
  for (const auto& [key, value] : required) {
    EXPECT_EQ(Parameters::defaults().at(key), value) << key;
  }
  for (const char* key : {"Grid/3D", "Icp/MaxCorrespondenceDistance", "Icp/PointToPlane"}) {
    EXPECT_TRUE(Parameters::isDeclared(key)) << key;
  }
  EXPECT_EQ(Parameters::info("Odom/Strategy").limits.choices.at(0).meaning, "Frame-to-Map (F2M)");
  EXPECT_EQ(Parameters::defaults().at("Bayes/PredictionLC"),
            "0.1 0.36 0.30 0.16 0.062 0.0151 0.00255 0.000324 2.5e-05 1.3e-06 4.8e-08 1.2e-09 "
            "1.9e-11 2.2e-13 1.7e-15 8.5e-18 2.9e-20 6.9e-23");
}

TEST(ParameterRegistry, CoversTheGroupsOfTheFoundationIssue) {
  const std::vector<std::string> groups = Parameters::groups();
  for (const char* group : {"Rtabmap", "Mem", "Kp", "Vis", "Reg", "Icp", "Odom", "OdomF2M", "RGBD",
                            "Grid", "GridGlobal", "Optimizer", "Bayes", "Db"}) {
    EXPECT_NE(std::find(groups.begin(), groups.end(), group), groups.end()) << group;
  }
}

TEST(ParameterRegistry, GeneratedKeyConstantsAndTypedDefaultsAgreeWithTheTable) {
  EXPECT_EQ(Parameters::kRtabmapDetectionRate(), "Rtabmap/DetectionRate");
  EXPECT_EQ(Parameters::kGrid3D(), "Grid/3D");
  EXPECT_EQ(Parameters::kDbSqlite3JournalMode(), "DbSqlite3/JournalMode");
  EXPECT_FLOAT_EQ(Parameters::defaultRtabmapLoopThr(), 0.11f);
  EXPECT_EQ(Parameters::defaultKpMaxFeatures(), 500);
  EXPECT_TRUE(Parameters::defaultMemIncrementalMemory());
  EXPECT_EQ(Parameters::defaultKpRoiRatios(), "0.0 0.0 0.0 0.0");
  EXPECT_DOUBLE_EQ(Parameters::defaultOptimizerEpsilon(), 1e-6);
  EXPECT_EQ(Parameters::info(Parameters::kOptimizerEpsilon()).defaultValue, "1e-06");
  EXPECT_EQ(Parameters::info(Parameters::kGridCellSize()).type, ParameterType::kFloat);
  EXPECT_EQ(Parameters::info(Parameters::kGFTTMinDistance()).type, ParameterType::kDouble);
  EXPECT_EQ(Parameters::info(Parameters::kMemSTMSize()).type, ParameterType::kInt);
  EXPECT_EQ(Parameters::info(Parameters::kRGBDEnabled()).type, ParameterType::kBool);
  EXPECT_EQ(Parameters::info(Parameters::kBayesPredictionLC()).type, ParameterType::kString);
}

TEST(ParameterRegistry, DefaultsMapHoldsEveryKey) {
  EXPECT_EQ(Parameters::defaults().size(), Parameters::all().size());
  for (const ParameterInfo& parameter : Parameters::all()) {
    EXPECT_EQ(Parameters::defaults().at(parameter.key), parameter.defaultValue);
    EXPECT_EQ(Parameters::find(parameter.key), &parameter);
  }
  EXPECT_EQ(Parameters::find("Rtabmap/Nope"), nullptr);
}

TEST(ParameterRegistry, OnlyImplementedBackEndsAreAccepted) {
  EXPECT_EQ(Parameters::defaults().at("Optimizer/Strategy"), "3");
  EXPECT_TRUE(Parameters::isValid("Optimizer/Strategy", "3"));
  std::string why;
  EXPECT_FALSE(Parameters::isValid("Optimizer/Strategy", "1", &why));  // g2o: not here
  EXPECT_NE(why.find("3 (Ceres)"), std::string::npos) << why;
  EXPECT_FALSE(Parameters::isValid("Kp/DetectorStrategy", "0"));  // SURF: no xfeatures2d
  EXPECT_TRUE(Parameters::isValid("Kp/DetectorStrategy", "8"));
}

TEST(ParameterRegistry, AParameterOfTheOriginalNotImplementedHereAcceptsOnlyItsDefault) {
  std::string why;
  EXPECT_TRUE(Parameters::isValid("Mem/LocalizationDataSaved", "false"));
  EXPECT_TRUE(Parameters::isValid("Mem/LocalizationDataSaved", "0"));
  EXPECT_FALSE(Parameters::isValid("Mem/LocalizationDataSaved", "true", &why));
  EXPECT_NE(why.find("Mem/LocalizationDataSaved"), std::string::npos) << why;
  EXPECT_NE(why.find("not implemented here (localization never writes to the database)"), std::string::npos) << why;
  EXPECT_NE(why.find("default \"false\""), std::string::npos) << why;
  EXPECT_TRUE(Parameters::isValid("Rtabmap/ImageBufferSize", "1"));
  EXPECT_FALSE(Parameters::isValid("Rtabmap/ImageBufferSize", "0"));
  EXPECT_TRUE(Parameters::isValid("OdomF2M/ValidDepthRatio", "0.750"));
  EXPECT_FALSE(Parameters::isValid("OdomF2M/ValidDepthRatio", "0.5"));
  // Its default is what happens here (merged nodes are never saved), not the original's true:
  // a launch file asking for false is accepted, one asking to keep them is told it cannot.
  EXPECT_TRUE(Parameters::isValid("Mem/NotLinkedNodesKept", "false"));
  EXPECT_FALSE(Parameters::isValid("Mem/NotLinkedNodesKept", "true", &why));
  EXPECT_NE(why.find("never saved"), std::string::npos) << why;
  EXPECT_FALSE(Parameters::isValid("Mem/LocalizationDataSaved", "maybe", &why));
  EXPECT_NE(why.find("not a bool"), std::string::npos) << why;
  EXPECT_EQ(Parameters::info("Mem/LocalizationDataSaved").expectation(), "its default only (not implemented here)");
}

// Every declared parameter is read by the code (core, tools, ROS layer), declared not
// implemented, or an enumeration of the one back end there is: a parameter accepted and then
// ignored is a setting a user believes in.
// Source text is searched for its key constant (kGroupName()) or its quoted key.
TEST(ParameterRegistry, EveryParameterIsReadByTheCodeOrDeclaredNotImplemented) {
  namespace fs = std::filesystem;
  const fs::path core(RTABMAP_CORE_SOURCE_DIR);
  std::string code;
  std::vector<fs::path> roots{core / "src", core / "tools", core / "include"};
  for (const fs::directory_entry& e : fs::directory_iterator(core.parent_path())) {
    const std::string name = e.path().filename().string();
    if (e.is_directory() && name.rfind("rtabmap_", 0) == 0 && name != "rtabmap_core") roots.push_back(e.path());
  }
  for (const fs::path& root : roots) {
    if (!fs::exists(root)) continue;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(root)) {
      const std::string ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".cpp" && ext != ".h")) continue;
      if (e.path().string().find("/params/") != std::string::npos) continue;  // the declarations
      std::ifstream in(e.path());
      std::stringstream text;
      text << in.rdbuf();
      code += text.str();
    }
  }
  ASSERT_GT(code.size(), 100000u) << "sources not found under " << core;
  for (const ParameterInfo& p : Parameters::all()) {
    const bool read = code.find("k" + p.group + p.name + "()") != std::string::npos ||
                      code.find("\"" + p.key + "\"") != std::string::npos;
    if (p.limits.choices.size() == 1) continue;  // one back end (Optimizer/Strategy): nothing to choose
    if (p.limits.notImplemented.empty()) {
      EXPECT_TRUE(read) << p.key << " is declared but nothing reads it: implement it or declare it NotImplemented";
    } else {
      EXPECT_FALSE(read) << p.key << " is read by the code but declared NotImplemented";
    }
  }
}

TEST(ParameterExpectation, DescribesTypeAndRangeInWords) {
  EXPECT_EQ(Parameters::info("Mem/RehearsalSimilarity").expectation(), "a float in [0, 1]");
  EXPECT_EQ(Parameters::info("Grid/CellSize").expectation(), "a float > 0");
  EXPECT_EQ(Parameters::info("Mem/STMSize").expectation(), "an int >= 0");
  EXPECT_EQ(Parameters::info("RGBD/Enabled").expectation(), "a bool (true, false, 1 or 0)");
  EXPECT_EQ(Parameters::info("Reg/Strategy").expectation(),
            "one of 0 (visual), 1 (ICP), 2 (visual then ICP)");
  EXPECT_EQ(Parameters::info("Kp/RoiRatios").expectation(),
            "4 numbers separated by spaces, each in [0, 1]");
  EXPECT_EQ(Parameters::info("Mem/ImageCompressionFormat").expectation(),
            "one of \".jpg\" (JPEG, lossy and small), \".png\" (PNG, lossless)");
  EXPECT_EQ(Parameters::info("Db/TargetVersion").expectation(), "text");
}

}  // namespace
}  // namespace rtabmap

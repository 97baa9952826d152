// The odometry nodes' private parameters: core keys validated with "did you mean" warnings,
// misspelled node parameters, and icp_odometry's scan options as Icp/ parameters.
#include <gtest/gtest.h>

#include "rtabmap_core/odometry/Odometry.h"
#include "rtabmap_odom/NodeParameters.h"

namespace rtabmap_odom {
namespace {

using rtabmap::Parameters;

TEST(NodeParameters, CoreKeysAreValidatedAndNodeParametersLeftOut) {
  const CoreParameters core = coreParametersFromPrivate(
      {{"Odom/Strategy", "1"}, {"Vis/MinInliers", "25"}, {"frame_id", "base_link"}, {"publish_tf", "true"}});
  EXPECT_EQ(core.parameters, (rtabmap::ParametersMap{{"Odom/Strategy", "1"}, {"Vis/MinInliers", "25"}}));
  EXPECT_TRUE(core.warnings.empty());
  // The odometry is built with them: Odom/Strategy 1 is frame-to-frame.
  EXPECT_EQ(rtabmap::Odometry::create(core.parameters)->type(), rtabmap::Odometry::Type::kF2F);
}

TEST(NodeParameters, UnknownCoreKeyIsIgnoredWithTheClosestKey) {
  const CoreParameters core = coreParametersFromPrivate({{"Odom/Stratgy", "1"}, {"Vis/MinInliers", "25"}});
  EXPECT_EQ(core.parameters.count("Odom/Stratgy"), 0u);
  EXPECT_EQ(core.parameters.count("Vis/MinInliers"), 1u);
  ASSERT_EQ(core.warnings.size(), 1u);
  EXPECT_NE(core.warnings[0].find("\"Odom/Stratgy\""), std::string::npos) << core.warnings[0];
  EXPECT_NE(core.warnings[0].find("did you mean \"Odom/Strategy\""), std::string::npos) << core.warnings[0];
}

TEST(NodeParameters, InvalidValueIsIgnoredWithTheReason) {
  // Odom/Strategy is 0 or 1; Icp/VoxelSize a float >= 0; a bool accepts true/false/1/0.
  const CoreParameters core = coreParametersFromPrivate(
      {{"Odom/Strategy", "7"}, {"Icp/VoxelSize", "big"}, {"Odom/GuessMotion", "false"}});
  EXPECT_EQ(core.parameters, (rtabmap::ParametersMap{{"Odom/GuessMotion", "false"}}));
  ASSERT_EQ(core.warnings.size(), 2u);
  EXPECT_NE(core.warnings[0].find("Icp/VoxelSize"), std::string::npos) << core.warnings[0];
  EXPECT_NE(core.warnings[1].find("Odom/Strategy"), std::string::npos) << core.warnings[1];
  EXPECT_NE(core.warnings[1].find("default 0"), std::string::npos) << core.warnings[1];
}

TEST(NodeParameters, MisspelledNodeParameterNamesTheClosestOne) {
  const std::vector<std::string> w = unknownNodeParameters(
      {{"frame_id", "base_link"}, {"odom_frameid", "odom"}, {"Odom/Strategy", "0"}}, {"frame_id", "odom_frame_id"});
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("\"odom_frameid\""), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("did you mean \"odom_frame_id\""), std::string::npos) << w[0];
}

TEST(NodeParameters, ScanOptionsBecomeIcpParameters) {
  ScanOptions o;
  o.rangeMin = 0.5;
  o.rangeMax = 30.0;
  o.voxelSize = 0.1;
  o.normalK = 10;
  ASSERT_TRUE(o.IsValid());
  const rtabmap::ParametersMap p = applyScanOptions(o, {{"Odom/Strategy", "0"}});
  EXPECT_FLOAT_EQ(Parameters::getFloat(p, Parameters::kIcpRangeMin()), 0.5f);
  EXPECT_FLOAT_EQ(Parameters::getFloat(p, Parameters::kIcpRangeMax()), 30.0f);
  EXPECT_FLOAT_EQ(Parameters::getFloat(p, Parameters::kIcpVoxelSize()), 0.1f);
  EXPECT_EQ(Parameters::getInt(p, Parameters::kIcpPointToPlaneK()), 10);
  // Options left at their "keep" value do not touch the core's defaults.
  EXPECT_EQ(p.count(Parameters::kIcpDownsamplingStep()), 0u);
  EXPECT_EQ(p.count(Parameters::kIcpPointToPlaneRadius()), 0u);
  EXPECT_EQ(p.at("Odom/Strategy"), "0");
  Parameters::validate(p);
}

TEST(NodeParameters, ExplicitCoreParameterWinsOverScanOption) {
  ScanOptions o;
  o.voxelSize = 0.1;
  std::vector<std::string> notes;
  const rtabmap::ParametersMap p = applyScanOptions(o, {{"Icp/VoxelSize", "0.2"}}, &notes);
  EXPECT_EQ(p.at("Icp/VoxelSize"), "0.2");
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("scan_voxel_size"), std::string::npos) << notes[0];
}

TEST(NodeParameters, InvalidScanOptionsNameTheParameter) {
  std::string why;
  ScanOptions o;
  o.rangeMin = 5.0;
  o.rangeMax = 2.0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("scan_range_min"), std::string::npos) << why;
  o = ScanOptions();
  o.normalK = -1;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("scan_normal_k"), std::string::npos) << why;
  o = ScanOptions();
  o.downsamplingStep = 0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("scan_downsampling_step"), std::string::npos) << why;
}

}  // namespace
}  // namespace rtabmap_odom

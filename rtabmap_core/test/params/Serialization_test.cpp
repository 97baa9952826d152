// The one-string form stored per session in the database.
#include <gtest/gtest.h>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
namespace {

TEST(ParameterSerialization, RoundTripsTrickyValues) {
  // The one free-text parameter, tricky then empty.
  for (const std::string& free : {std::string("a;b=c%d e\nf\r\tg ; == %25 %"), std::string()}) {
    const ParametersMap parameters = {
        {"Db/TargetVersion", free},
        {"Rtabmap/DetectionRate", "2.5"},
        {"Kp/RoiRatios", "0 0 0.1 0.2"},
        {"Mem/ImageCompressionFormat", ".png"},
    };
    const std::string text = Parameters::serialize(parameters);
    EXPECT_EQ(text.find('\n'), std::string::npos) << text;
    EXPECT_EQ(Parameters::deserialize(text), parameters);
  }
}

TEST(ParameterSerialization, RoundTripsArbitraryBytesAndUnicode) {
  std::string allBytes;
  for (int c = 1; c < 256; ++c) allBytes += static_cast<char>(c);
  const ParametersMap parameters = {{"Db/TargetVersion", allBytes + "\xC3\xA9t\xC3\xA9 \xE2\x9C\x93"}};
  const std::string text = Parameters::serialize(parameters);
  EXPECT_NE(text.find("\xC3\xA9t\xC3\xA9"), std::string::npos) << "UTF-8 stays readable";
  EXPECT_EQ(Parameters::deserialize(text), parameters);
}

TEST(ParameterSerialization, RoundTripsTheWholeDefaultMap) {
  EXPECT_EQ(Parameters::deserialize(Parameters::serialize(Parameters::defaults())),
            Parameters::defaults());
  EXPECT_EQ(Parameters::serialize({}), "");
  EXPECT_TRUE(Parameters::deserialize("").empty());
}

TEST(ParameterSerialization, FormatIsReadableKeyValuePairs) {
  EXPECT_EQ(Parameters::serialize({{"Kp/MaxFeatures", "400"}, {"Mem/STMSize", "20"}}),
            "Kp/MaxFeatures=400;Mem/STMSize=20");
  EXPECT_EQ(Parameters::serialize({{"Db/TargetVersion", "a;b=c%"}}),
            "Db/TargetVersion=a%3Bb%3Dc%25");
}

TEST(ParameterSerialization, LenientModeSetsAsideUnknownKeysAndInvalidValues) {
  const std::string fromOtherVersion =
      "Kp/MaxFeatures=400;Future/Knob=x%3By;Optimizer/Strategy=1;Mem/STMSize=20;";
  const DeserializedParameters result = Parameters::deserializeLenient(fromOtherVersion);
  EXPECT_EQ(result.known, (ParametersMap{{"Kp/MaxFeatures", "400"}, {"Mem/STMSize", "20"}}));
  EXPECT_EQ(result.unknown, (ParametersMap{{"Future/Knob", "x;y"}}));
  EXPECT_EQ(result.invalid, (ParametersMap{{"Optimizer/Strategy", "1"}}));
}

TEST(ParameterSerialization, StrictModeRejectsUnknownKeysNamingThem) {
  try {
    Parameters::deserialize("Kp/MaxFeatures=400;Future/Knob=1");
    FAIL() << "expected a ParameterError";
  } catch (const ParameterError& error) {
    EXPECT_NE(std::string(error.what()).find("Future/Knob"), std::string::npos) << error.what();
  }
  EXPECT_THROW(Parameters::deserialize("Kp/MaxFeatures=lots"), ParameterError);
}

TEST(ParameterSerialization, CorruptTextThrowsInBothModes) {
  for (const char* corrupt : {"Kp/MaxFeatures", "Kp/MaxFeatures=4%0", "Kp/MaxFeatures=4%zz",
                              "Kp/MaxFeatures=1;Mem/STMSize"}) {
    EXPECT_THROW(Parameters::deserialize(corrupt), ParameterError) << corrupt;
    EXPECT_THROW(Parameters::deserializeLenient(corrupt), ParameterError) << corrupt;
  }
  try {
    Parameters::deserializeLenient("Kp/MaxFeatures=1;Mem/STMSize");
  } catch (const ParameterError& error) {
    EXPECT_NE(std::string(error.what()).find("\"Mem/STMSize\""), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace rtabmap

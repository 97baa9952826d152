#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "common/Json.h"

namespace rtabmap::tools {
namespace {

TEST(JsonLine, PrintsOneCompactLineThatParsesBack) {
  const nlohmann::json summary = {{"version", "0.1.0"},
                                  {"nodes", 1200},
                                  {"links", {{"neighbor", 1199}, {"loop", 12}}},
                                  {"label", "line one\nline two"}};
  std::ostringstream out;
  out << "some human text first\n";
  printJsonLine(summary, out);
  const std::string text = out.str();
  ASSERT_EQ(text.back(), '\n');
  const std::string lastLine = text.substr(text.rfind('\n', text.size() - 2) + 1);
  EXPECT_EQ(std::count(lastLine.begin(), lastLine.end(), '\n'), 1);
  EXPECT_EQ(nlohmann::json::parse(lastLine), summary);
  EXPECT_EQ(toJsonLine({{"a", 1}}), "{\"a\":1}");
}

TEST(JsonLine, InvalidUtf8IsReplacedInsteadOfThrowing) {
  const std::string line = toJsonLine({{"label", std::string("caf\xE9")}});
  EXPECT_NO_THROW(nlohmann::json::parse(line));
  EXPECT_NE(line.find("caf\xEF\xBF\xBD"), std::string::npos) << line;
}

}  // namespace
}  // namespace rtabmap::tools

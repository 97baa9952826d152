// The listing printed by every tool's --params.
#include <gtest/gtest.h>

#include <sstream>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
namespace {

TEST(ParameterPrinting, ListsEveryKeyWithDefaultRangeAndDescription) {
  std::ostringstream out;
  Parameters::print(out);
  const std::string text = out.str();
  for (const ParameterInfo& parameter : Parameters::all()) {
    EXPECT_NE(text.find("\n" + parameter.key + " = "), std::string::npos) << parameter.key;
    EXPECT_NE(text.find(parameter.description), std::string::npos) << parameter.key;
  }
  EXPECT_NE(text.find("\nGrid/CellSize = 0.05   (a float > 0)\n"), std::string::npos);
  EXPECT_NE(text.find("\n[Icp]\n"), std::string::npos);
}

TEST(ParameterPrinting, ShowsCurrentValuesBesideTheirDefault) {
  std::ostringstream out;
  Parameters::print(out, {{"Grid/CellSize", "0.1"}});
  EXPECT_NE(out.str().find("\nGrid/CellSize = 0.1   (default 0.05; a float > 0)\n"),
            std::string::npos);
  std::ostringstream ignored;
  EXPECT_THROW(Parameters::print(ignored, {{"Grid/CellSize", "big"}}), ParameterError);
}

}  // namespace
}  // namespace rtabmap

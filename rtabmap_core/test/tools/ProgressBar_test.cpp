#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "common/ProgressBar.h"

namespace rtabmap::tools {
namespace {

TEST(ProgressFormat, ShowsBarCountRateAndEta) {
  EXPECT_EQ(formatProgress("images", 450, 1000, 45.0),
            "images [#########-----------]  45% 450/1000  10.0/s  ETA 0:55");
  EXPECT_EQ(formatProgress("images", 1000, 1000, 3725.0),
            "images [####################] 100% 1000/1000  0.3/s  elapsed 1:02:05");
  EXPECT_EQ(formatProgress("scans", 0, 10, 0.0), "scans [--------------------]   0% 0/10");
}

TEST(ProgressFormat, UnknownTotalShowsCountAndRateOnly) {
  EXPECT_EQ(formatProgress("nodes", 2500, 0, 2.0), "nodes 2500  1250/s  elapsed 0:02");
}

TEST(ProgressFormat, Durations) {
  EXPECT_EQ(formatDuration(0), "0:00");
  EXPECT_EQ(formatDuration(59.6), "1:00");
  EXPECT_EQ(formatDuration(3600), "1:00:00");
  EXPECT_EQ(formatDuration(-5), "0:00");
}

TEST(ProgressBar, QuietModeWritesOnlyTheFinalLine) {
  std::ostringstream err;
  {
    ProgressBar bar("frames", 3, /*live=*/false, err);
    for (int i = 0; i < 3; ++i) bar.increment();
    EXPECT_TRUE(err.str().empty());
  }  // the destructor finishes
  const std::string text = err.str();
  EXPECT_EQ(text.rfind("frames [####################] 100% 3/3", 0), 0u) << text;
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1);
}

TEST(ProgressBar, LiveModeRedrawsInPlaceThrottled) {
  std::ostringstream err;
  ProgressBar bar("frames", 1000, /*live=*/true, err);
  for (int i = 1; i <= 1000; ++i) bar.update(i);  // far faster than the redraw period
  const std::string drawn = err.str();
  const auto redraws = std::count(drawn.begin(), drawn.end(), '\r');
  EXPECT_GE(redraws, 1);
  EXPECT_LE(redraws, 3) << "updates must be throttled";
  bar.finish();
  bar.finish();  // idempotent
  const std::string text = err.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1);
  EXPECT_NE(text.find("1000/1000"), std::string::npos);
  EXPECT_EQ(bar.done(), 1000u);
}

}  // namespace
}  // namespace rtabmap::tools

// Regression tests of the ROS conversion fuzz targets (fuzz/targets/ros_*.cpp): every input
// that once crashed a conversion is kept in fuzz/regressions/ros_<target>/ and replayed through
// the same entry (fuzz/ros/RosEntries.h), here in the normal build of `make test`. *.rejected
// files must now be refused, *.accepted converted; a crash kills the test.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "../../fuzz/ros/RosEntries.h"

namespace {

namespace fs = std::filesystem;
using rtabmap::fuzz::RosOutcome;

struct RosTarget {
  const char* name;
  RosOutcome (*entry)(const uint8_t*, size_t);
};

// gtest names a failing case by the target, not by the bytes of the struct.
void PrintTo(const RosTarget& target, std::ostream* os) { *os << target.name; }

const RosTarget kRosTargets[] = {{"ros_camera_info", rtabmap::fuzz::fuzzCameraInfo},
                                 {"ros_laser_scan", rtabmap::fuzz::fuzzLaserScan},
                                 {"ros_point_cloud2", rtabmap::fuzz::fuzzPointCloud2},
                                 {"ros_rgbd_image", rtabmap::fuzz::fuzzRgbdImage}};

class RosFuzzTargets : public ::testing::TestWithParam<RosTarget> {};

TEST_P(RosFuzzTargets, KeptCrashInputsAreHandled) {
  const fs::path dir = fs::path(RTABMAP_ROS_SOURCE_DIR) / "fuzz" / "regressions" / GetParam().name;
  std::vector<fs::path> files;
  if (fs::is_directory(dir)) {
    for (const auto& e : fs::directory_iterator(dir)) {
      if (e.is_regular_file()) files.push_back(e.path());
    }
  }
  if (files.empty()) GTEST_SKIP() << "no regression input kept for " << GetParam().name;
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.string());
    std::ifstream in(file, std::ios::binary);
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    const RosOutcome outcome = GetParam().entry(bytes.data(), bytes.size());
    if (file.extension() == ".rejected") {
      EXPECT_EQ(outcome, RosOutcome::kRejected);
    }
    if (file.extension() == ".accepted") {
      EXPECT_EQ(outcome, RosOutcome::kAccepted);
    }
  }
}

// No bytes: every field zero (no size, no ranges, no fields, no image). Each conversion must
// refuse it, which shows the entries do reach the conversions.
TEST_P(RosFuzzTargets, AllZeroMessageIsRefused) {
  const std::vector<uint8_t> none;
  EXPECT_EQ(GetParam().entry(none.data(), 0), RosOutcome::kRejected);
}

INSTANTIATE_TEST_SUITE_P(Fuzz, RosFuzzTargets, ::testing::ValuesIn(kRosTargets),
                         [](const ::testing::TestParamInfo<RosTarget>& info) { return std::string(info.param.name); });

}  // namespace

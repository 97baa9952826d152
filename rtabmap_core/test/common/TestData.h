#pragma once
// Helpers for tests that read the real datasets in ../shared/data (beside the repository) or
// write temporary files. Tests needing the datasets skip with a clear message when absent, so a
// fresh clone still passes.
#include <gtest/gtest.h>

#include <string>

namespace rtabmap::test {

// $RTABMAP_DATA_DIR if set, else <repo>/../shared/data; "" if that folder does not exist.
std::string sharedDataDir();
// sharedDataDir() + "/" + relative, or "" if the data folder or this entry is missing.
std::string sharedDataPath(const std::string& relative);
// A fresh empty directory under the system temp dir, removed by ~TempDir.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "rtabmap_test");
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};
// Path of a built command-line tool (rtabmap-<name>).
std::string toolPath(const std::string& toolName);
// The seed of a synthetic scene's random draw: `seed` + $RTABMAP_TEST_DRAW (0 when unset). The
// tests run draw 0; `make test-draws` runs the suites built on the synthetic scenes over other
// draws, so a bound that holds only for the draw it was tuned on shows up.
unsigned drawSeed(unsigned seed);

}  // namespace rtabmap::test

// Skips the current test when a dataset entry is absent: RTABMAP_REQUIRE_DATA(path, "radish/intel.clf.bz2");
#define RTABMAP_REQUIRE_DATA(var, relative)                                              \
  const std::string var = ::rtabmap::test::sharedDataPath(relative);                      \
  if (var.empty()) {                                                                      \
    GTEST_SKIP() << "needs ../shared/data/" << relative                                   \
                 << " (absent on this machine; set RTABMAP_DATA_DIR to run it)";          \
  }

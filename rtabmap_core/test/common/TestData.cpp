#include "common/TestData.h"

#include <cstdlib>
#include <filesystem>
#include <random>

namespace fs = std::filesystem;

namespace rtabmap::test {

std::string sharedDataDir() {
  const char* env = std::getenv("RTABMAP_DATA_DIR");
  fs::path dir = (env && *env) ? fs::path(env)
                               : fs::path(RTABMAP_CORE_SOURCE_DIR) / ".." / ".." / "shared" / "data";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return "";
  return fs::weakly_canonical(dir, ec).string();
}

unsigned drawSeed(unsigned seed) {
  const char* env = std::getenv("RTABMAP_TEST_DRAW");
  return seed + ((env && *env) ? static_cast<unsigned>(std::strtoul(env, nullptr, 10)) : 0u);
}

std::string sharedDataPath(const std::string& relative) {
  const std::string dir = sharedDataDir();
  if (dir.empty()) return "";
  fs::path p = fs::path(dir) / relative;
  std::error_code ec;
  return fs::exists(p, ec) ? p.string() : "";
}

TempDir::TempDir(const std::string& prefix) {
  std::random_device rd;
  for (int attempt = 0; attempt < 100; ++attempt) {
    fs::path p = fs::temp_directory_path() / (prefix + "_" + std::to_string(rd()));
    std::error_code ec;
    if (fs::create_directory(p, ec)) {
      path_ = p.string();
      return;
    }
  }
  throw std::runtime_error("cannot create a temporary directory");
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

std::string toolPath(const std::string& toolName) {
  return (fs::path(RTABMAP_CORE_TOOLS_DIR) / ("rtabmap-" + toolName)).string();
}

}  // namespace rtabmap::test

#pragma once
// Helpers shared by the eval tests: the shipped Radish data, small files, bzip2 compression,
// reading a whole dataset.
#include <bzlib.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "common/TestData.h"
#include "rtabmap_core/eval/DatasetReader.h"

namespace rtabmap::test {

// <repo>/data/<relative> (shipped with the project), else ../shared/data/<relative>, else "".
inline std::string shippedDataPath(const std::string& relative) {
  const std::filesystem::path shipped = std::filesystem::path(RTABMAP_CORE_SOURCE_DIR) / ".." / "data" / relative;
  std::error_code ec;
  if (std::filesystem::exists(shipped, ec)) return shipped.lexically_normal().string();
  return sharedDataPath(relative);
}

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  ASSERT_TRUE(static_cast<bool>(f)) << path;
}

inline std::string readText(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

// One bzip2 stream of `text` (libbz2, block size 9).
inline std::string bz2Compress(const std::string& text) {
  std::vector<char> out(text.size() + text.size() / 100 + 700);
  unsigned int size = static_cast<unsigned int>(out.size());
  const int rc = BZ2_bzBuffToBuffCompress(out.data(), &size, const_cast<char*>(text.data()),
                                          static_cast<unsigned int>(text.size()), 9, 0, 0);
  EXPECT_EQ(rc, BZ_OK);
  return std::string(out.data(), size);
}

inline std::vector<DatasetRecord> readAll(DatasetReader& reader) {
  std::vector<DatasetRecord> records;
  DatasetRecord r;
  while (reader.next(r)) records.push_back(r);
  return records;
}

inline std::vector<DatasetRecord> readAll(const std::string& format, const std::string& path,
                                          const DatasetReaderOptions& options = {}) {
  auto reader = openDatasetReader(format, path, options);
  return readAll(*reader);
}

}  // namespace rtabmap::test

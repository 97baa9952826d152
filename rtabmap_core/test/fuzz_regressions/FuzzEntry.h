#pragma once
// The entry functions of the fuzz targets (fuzz/targets/*.cpp), shared with the regression
// tests (Regressions_test.cpp) so a crashing input found by libFuzzer is replayed through
// exactly the code that crashed.
//
// Contract of every entry: the parser either accepts the bytes or rejects them with
// rtabmap::Error (FormatError, DatabaseError, ParameterError) - the documented way every parser
// of outside data fails. Anything else (another exception type escaping, a crash, a sanitizer
// report, a hang) is a bug: libFuzzer reports an escaping exception as a crash (abort).
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "rtabmap_core/common/Error.h"

namespace rtabmap::fuzz {

enum class Outcome { kAccepted, kRejected };

// Runs body(); an rtabmap::Error means "rejected" (correct behaviour on bad input).
template <typename Body>
Outcome guarded(Body&& body) {
  try {
    body();
    return Outcome::kAccepted;
  } catch (const rtabmap::Error&) {
    return Outcome::kRejected;
  }
}

inline std::string asText(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// Parsers that only read paths get the bytes through a file private to this process (one per
// extension, rewritten at each input: no file accumulates while fuzzing).
inline std::string writeScratchFile(const uint8_t* data, size_t size, const std::string& extension) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
      ("rtabmap_fuzz_" + std::to_string(::getpid()) + extension);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path.string();
}

}  // namespace rtabmap::fuzz

#pragma once
// Defines the libFuzzer entry points of one target from an entry function of
// FuzzEntry.h / RosEntries.h. The library's log is limited to errors: a rejected input is the
// normal case and its warnings would drown the fuzzer's own output.
#include <cstddef>
#include <cstdint>

#include "rtabmap_core/common/Log.h"

#define RTABMAP_FUZZ_TARGET(entry)                                         \
  extern "C" int LLVMFuzzerInitialize(int*, char***) {                     \
    rtabmap::setLogLevel(rtabmap::LogLevel::kError);                       \
    return 0;                                                              \
  }                                                                        \
  extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) { \
    entry(data, size);                                                     \
    return 0;                                                              \
  }

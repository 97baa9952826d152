// The process's memory accounting and the heap release each update ends with (issue 10, the
// soak's memory goal: the resident size follows the live data, not the largest update so far).
#include <gtest/gtest.h>

#include <vector>

#include "../common/HeapHoles.h"
#include "rtabmap_core/memory/ProcessMemory.h"

namespace rtabmap::memory {
namespace {

constexpr size_t kMb = 1024 * 1024;

TEST(ProcessMemory, ResidentMemoryReadsTheSizesTheSystemCounts) {
  const Resident r = residentMemory();
  if (r.total == 0) GTEST_SKIP() << "no /proc/self/status here";
  EXPECT_GT(r.anon, 0u);
  EXPECT_GT(r.file, 0u);  // the test binary's own code
  EXPECT_LE(r.anon + r.file, r.total + kMb);  // plus shared memory, within rounding
  // 32 MB touched shows up as 32 MB more.
  std::vector<char> bulk(32 * kMb, 1);
  const Resident after = residentMemory();
  EXPECT_GE(after.total, r.total + 30 * kMb);
  EXPECT_EQ(bulk[12345], 1);
}

TEST(ProcessMemory, ReleaseFreedHeapGivesTheFreedPagesBack) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "the heap release is glibc's malloc_trim";
#endif
  if (residentMemory().total == 0) GTEST_SKIP() << "no /proc/self/status here";
  test::HeapHole hole(64 * kMb);
  const size_t held = residentMemory().anon;
  EXPECT_GE(heapStats().free, 60 * kMb) << "the freed blocks are malloc's free memory";
  releaseFreedHeap();
  const size_t released = residentMemory().anon;
  // The 64 MB were resident before (free() keeps what is below a block in use) and not after.
  EXPECT_LE(released + 48 * kMb, held) << "held " << held / kMb << " MB, after the release " << released / kMb;
}

}  // namespace
}  // namespace rtabmap::memory

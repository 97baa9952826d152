// The process's memory accounting and the heap release each update ends with (issue 10, the
// soak's memory goal: the resident size follows the live data, not the largest update so far).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

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
  if (test::kMallocReplacedBySanitizer) GTEST_SKIP() << "a sanitizer replaces glibc's malloc in this build";
  if (residentMemory().total == 0) GTEST_SKIP() << "no /proc/self/status here";
  test::HeapHole hole(64 * kMb);
  const size_t held = residentMemory().anon;
  EXPECT_GE(heapStats().free, 60 * kMb) << "the freed blocks are malloc's free memory";
  releaseFreedHeap();
  const size_t released = residentMemory().anon;
  // The 64 MB were resident before (free() keeps what is below a block in use) and not after.
  EXPECT_LE(released + 48 * kMb, held) << "held " << held / kMb << " MB, after the release " << released / kMb;
}

#if defined(__GLIBC__)
// The arenas of the process: malloc_info writes one <heap nr="..."> element each.
int arenaCount() {
  char* text = nullptr;
  size_t length = 0;
  FILE* out = open_memstream(&text, &length);
  malloc_info(0, out);
  std::fclose(out);
  int arenas = 0;
  for (const char* p = text; (p = std::strstr(p, "<heap nr=")) != nullptr; ++p) ++arenas;
  std::free(text);
  return arenas;
}

// Eight threads alive together, each allocating: glibc gives each an arena of its own while
// there are fewer than its limit (8 per core by default).
void allocateOnEightThreadsAtOnce() {
  constexpr int kThreads = 8;
  std::atomic<int> started{0};
  std::vector<std::thread> threads;
  for (int i = 0; i < kThreads; ++i) {
    threads.emplace_back([&started] {
      void* block = std::malloc(1024);
      std::memset(block, 1, 1024);
      ++started;
      while (started.load() < kThreads) std::this_thread::yield();
      std::free(block);
    });
  }
  for (std::thread& t : threads) t.join();
}
#endif

TEST(ProcessMemory, ConfigureAllocatorCapsTheArenasOfThreadsAllocatingTogether) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "the allocator set-up is glibc's mallopt";
#else
  if (test::kMallocReplacedBySanitizer) GTEST_SKIP() << "a sanitizer replaces glibc's malloc in this build";
  for (const char* chosen : {"MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_", "MALLOC_ARENA_MAX", "GLIBC_TUNABLES"}) {
    if (std::getenv(chosen)) GTEST_SKIP() << chosen << " is set: the user's allocator settings win";
  }
  // In a new process (the death test's "threadsafe" style runs the binary again for this test
  // alone): the setting is once per process, and glibc fixes its arena limit for good once a
  // process has more than eight arenas, which the tests before this one may have made.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const auto capped = [] {
    const bool applied = configureAllocator();
    const int before = arenaCount();
    allocateOnEightThreadsAtOnce();
    const int after = arenaCount();
    std::fprintf(stderr, "applied %d, arenas %d before, %d after eight threads allocated at once\n", applied ? 1 : 0,
                 before, after);
    std::_Exit(applied && after <= std::max(before, kArenaMax) ? 0 : 1);
  };
  EXPECT_EXIT(capped(), ::testing::ExitedWithCode(0), "applied 1, arenas");
#endif
}

}  // namespace
}  // namespace rtabmap::memory

#include "rtabmap_core/memory/ProcessMemory.h"

#include <sqlite3.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace rtabmap::memory {

HeapStats heapStats() {
  HeapStats h;
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 m = mallinfo2();
  h.inUse = m.uordblks + m.hblkhd;  // chunks in use in the arenas + blocks mmap()ed on their own
  h.free = m.fordblks;
#endif
  return h;
}

Resident residentMemory() {
  Resident r;
  std::ifstream status("/proc/self/status");
  std::string line;
  const auto field = [&line](const char* key, size_t& out) {
    const size_t n = std::strlen(key);
    if (line.compare(0, n, key) == 0) out = static_cast<size_t>(std::stoull(line.substr(n))) * 1024;  // kB
  };
  while (std::getline(status, line)) {
    field("VmRSS:", r.total);
    field("RssAnon:", r.anon);
    field("RssFile:", r.file);
  }
  return r;
}

void releaseFreedHeap() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

size_t sqliteInUse() { return static_cast<size_t>(sqlite3_memory_used()); }

bool configureAllocator() {
#if defined(__GLIBC__)
  static const bool applied = [] {
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    if (std::getenv("MALLOC_MMAP_THRESHOLD_") || std::getenv("MALLOC_TRIM_THRESHOLD_") ||
        std::getenv("MALLOC_ARENA_MAX") || (tunables && std::strstr(tunables, "glibc.malloc."))) {
      return false;  // the user's choice
    }
    return mallopt(M_MMAP_THRESHOLD, static_cast<int>(kMmapThreshold)) == 1 &&
           mallopt(M_TRIM_THRESHOLD, static_cast<int>(kTrimThreshold)) == 1 &&
           mallopt(M_ARENA_MAX, kArenaMax) == 1;
  }();
  return applied;
#else
  return false;
#endif
}

}  // namespace rtabmap::memory

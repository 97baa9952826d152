#include "rtabmap_core/memory/ProcessMemory.h"

#include <sqlite3.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace rtabmap::memory {

size_t heapInUse() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;  // chunks in use in the arenas + blocks mmap()ed on their own
#else
  return 0;
#endif
}

size_t heapFree() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  return mallinfo2().fordblks;
#else
  return 0;
#endif
}

size_t sqliteInUse() { return static_cast<size_t>(sqlite3_memory_used()); }

}  // namespace rtabmap::memory

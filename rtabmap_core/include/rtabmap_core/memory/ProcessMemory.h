#pragma once
// Where the process's RAM goes, for the statistics (issue 10, the soak's memory goal): the
// resident size (what the OS counts) is the heap's live data, plus what the allocator keeps free
// for later (fragmentation, per-thread arenas), plus code and stacks. These split the first two.
#include <cstddef>

namespace rtabmap::memory {

// inUse: bytes malloc handed out and did not get back, over all arenas (live heap data);
// free: bytes malloc holds from the OS and keeps free for later allocations, what a resident
// size larger than inUse is made of besides code and stacks. Both 0 where the C library cannot
// tell. One call for both: glibc walks every free chunk of every arena to count them (a few ms
// on a fragmented heap).
struct HeapStats {
  size_t inUse = 0, free = 0;
};
HeapStats heapStats();
// Bytes SQLite holds: page caches of every connection, prepared statements, schemas.
size_t sqliteInUse();

// Sets glibc's allocator up for a long mapping run (issue 10), once per process, before the
// mapping starts: blocks of kMmapThreshold bytes or more (images, depth, scans: 150-300 KB at
// 320x240) get their own mmap() and go back to the system when freed. glibc's default raises its
// threshold to the largest block freed so far, after which such buffers are carved from the heap
// between long-lived allocations and the heap fragments: what malloc keeps free then grows with
// the run and malloc_trim cannot return it. The trim threshold is fixed too (glibc raises it with
// the mmap threshold). Not applied where the user set them (MALLOC_MMAP_THRESHOLD_,
// MALLOC_TRIM_THRESHOLD_, GLIBC_TUNABLES) nor elsewhere than glibc. Returns whether it applied.
constexpr size_t kMmapThreshold = 128 * 1024;
constexpr size_t kTrimThreshold = 4 * 1024 * 1024;
bool configureAllocator();

}  // namespace rtabmap::memory

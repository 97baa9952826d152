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
// The process's resident size (what the OS counts, /proc/self/status), in bytes: all of it,
// anonymous (heap, arenas, mapped blocks) and file-backed (code, mapped files). Zeros where
// /proc is not there.
struct Resident {
  size_t total = 0, anon = 0, file = 0;
};
Resident residentMemory();

// Bytes SQLite holds: page caches of every connection, prepared statements, schemas.
size_t sqliteInUse();

// Sets glibc's allocator up for a long mapping run (issue 10), once per process, before the
// mapping starts: blocks of kMmapThreshold bytes or more (images, depth, scans: 150-300 KB at
// 320x240) get their own mmap() and go back to the system when freed. glibc's default raises its
// threshold to the largest block freed so far, after which such buffers are carved from the heap
// between long-lived allocations and the heap fragments: what malloc keeps free then grows with
// the run and malloc_trim cannot return it. The trim threshold is fixed too (glibc raises it with
// the mmap threshold). And the arenas are capped at kArenaMax: glibc gives each thread an arena
// of its own at its first allocation, up to 8 per core, and a freed block goes back to the arena
// it came from, where only that arena's threads reuse it; the node's threads (callbacks, the map
// assembly, the database writer, the ray caster, the vocabulary's rebuild) can each keep free
// space the others cannot use, in pages partly in use that malloc_trim cannot give back (the
// soak found most of it in the update's own arena all the same: README, Reliability). Arenas made
// before the call stay (the ROS threads started before the nodelet's), and the cap only holds in
// a process that has not had more than eight yet (glibc then fixes its limit for good): call it
// at start. Not applied where the user set them (MALLOC_MMAP_THRESHOLD_, MALLOC_TRIM_THRESHOLD_,
// MALLOC_ARENA_MAX, GLIBC_TUNABLES) nor elsewhere than glibc. Returns whether it applied.
constexpr size_t kMmapThreshold = 128 * 1024;
constexpr size_t kTrimThreshold = 4 * 1024 * 1024;
constexpr int kArenaMax = 2;
bool configureAllocator();

// Gives the free pages inside the heap back to the system (glibc's malloc_trim). Freed memory
// stays resident otherwise: glibc keeps it for reuse and only ever returns the top of the heap,
// while the long-lived allocations made meanwhile (words, links, grid tiles) pin what lies below.
// An update frees far more than it keeps (retrieved nodes, local grids read back for a
// re-assembly, the locations transferred to the LTM), so a trim once per update keeps the
// resident size near the live data instead of near the largest update so far. It walks every
// arena: a few ms on a heap of a few hundred MB. No-op elsewhere than glibc.
void releaseFreedHeap();

}  // namespace rtabmap::memory

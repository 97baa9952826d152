#pragma once
// Where the process's RAM goes, for the statistics (issue 10, the soak's memory goal): the
// resident size (what the OS counts) is the heap's live data, plus what the allocator keeps free
// for later (fragmentation, per-thread arenas), plus code and stacks. These split the first two.
#include <cstddef>

namespace rtabmap::memory {

// Bytes malloc handed out and did not get back, over all arenas (live heap data). 0 where the
// C library cannot tell.
size_t heapInUse();
// Bytes malloc holds from the OS and keeps free for later allocations (0 where unknown): what a
// resident size larger than heapInUse() is made of, besides code and stacks.
size_t heapFree();
// Bytes SQLite holds: page caches of every connection, prepared statements, schemas.
size_t sqliteInUse();

}  // namespace rtabmap::memory

#pragma once
// A heap with a hole the allocator cannot give back by itself (tests of
// memory::releaseFreedHeap, issue 10): `bytes` in 16 KB blocks (under glibc's mmap threshold, so
// they come from the heap), touched so they are resident, then freed while a block allocated
// after them stays in use. free() only ever returns the top of the heap to the system: these
// pages stay resident until something trims the heap.
#include <cstdlib>
#include <cstring>
#include <vector>

namespace rtabmap::test {

// AddressSanitizer and ThreadSanitizer replace malloc (make test-asan / test-tsan): glibc's heap,
// its trim, statistics and arenas, which these tests measure, is then not the allocator running.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kMallocReplacedBySanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
inline constexpr bool kMallocReplacedBySanitizer = true;
#else
inline constexpr bool kMallocReplacedBySanitizer = false;
#endif
#else
inline constexpr bool kMallocReplacedBySanitizer = false;
#endif

class HeapHole {
 public:
  explicit HeapHole(size_t bytes) {
    std::vector<void*> blocks;
    for (size_t done = 0; done < bytes; done += kBlock) {
      void* b = std::malloc(kBlock);
      std::memset(b, 1, kBlock);
      blocks.push_back(b);
    }
    pin_ = std::malloc(kBlock);
    std::memset(pin_, 1, kBlock);
    for (void* b : blocks) std::free(b);
  }
  ~HeapHole() { std::free(pin_); }
  HeapHole(const HeapHole&) = delete;
  HeapHole& operator=(const HeapHole&) = delete;

 private:
  static constexpr size_t kBlock = 16 * 1024;
  void* pin_ = nullptr;
};

}  // namespace rtabmap::test

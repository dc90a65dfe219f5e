// Include in exactly one file of a fuzz target: replaces the plain operator new / delete with ones over
// malloc / free (so ASan still guards every block) that
// - throw std::bad_alloc for allocations over 64 MiB. Under ASan a failed operator new aborts the process
//   instead of throwing; this puts back what a real machine does, for targets whose third-party library
//   allocates sizes read from the file before reading the data (the reader under test must turn that
//   std::bad_alloc into an mv::Error). 64 MiB (no seed needs a tenth of that): OpenVDB copies a metadata record
//   of a size the file declares several times over (fuzz/known/), and several such blocks at once below a
//   limit near the 2 GiB RSS limit would still end in an out-of-memory. megavox's own huge allocations still
//   stop the fuzzer, as a bad_alloc that escapes the reader (std::terminate) or as an out-of-memory.
// - keep large blocks (128 KiB and more) for the next allocation instead of freeing them (LargeBlocks below).
//   ASan serves each such block from a fresh mmap and unmaps it on free, so every input paid for its page
//   faults again: assimp's OBJ importer fills two 16 MiB buffers per file, which was 80 % of fuzz_mesh_assimp's
//   time (BENCHMARKS.md, "Fuzzing").
// fuzz_vdb takes the limit without the reuse (MV_REUSE_LARGE_BLOCKS 0: fuzz_vdb.cpp says why). The sanitized test
// suite (tests/sanitizer_new.cpp) takes neither (MV_THROWING_NEW_LIMIT 0 too): there only a malloc that fails
// (ASAN_OPTIONS=allocator_may_return_null=1) throws.
#pragma once
#include <cstdint>
#include <cstdlib>
#include <new>

#ifndef MV_THROWING_NEW_LIMIT
#define MV_THROWING_NEW_LIMIT (std::size_t{1} << 26)
#endif
#ifndef MV_REUSE_LARGE_BLOCKS
#define MV_REUSE_LARGE_BLOCKS 1
#endif

#if MV_REUSE_LARGE_BLOCKS
#include <sanitizer/allocator_interface.h>
#include <sanitizer/asan_interface.h>
#include <sanitizer/lsan_interface.h>

#include <bit>
#include <mutex>
#endif

namespace mv::fuzz {
inline constexpr std::size_t kMaxAllocation = MV_THROWING_NEW_LIMIT ? MV_THROWING_NEW_LIMIT : SIZE_MAX;

#if MV_REUSE_LARGE_BLOCKS
// Blocks of 128 KiB to 64 MiB (ASan serves those from mmap: its size classes end at 128 KiB) are malloc'ed at
// the next power of two, which marks them as these blocks when deleted, and kept then (up to 32 of them,
// 256 MiB in all) for the next request they fit (the smallest that does). Blocks a library leaks are simply
// not given back. ASan's checks stay: the part of a block past the size asked for, and the whole of a kept
// block, are poisoned, so an overflow or a use after delete is still reported (as a use-after-poison). Leaks
// are checked in a block's first life only (take).
class LargeBlocks {
 public:
  static constexpr std::size_t kMin = std::size_t{1} << 17, kMax = std::size_t{1} << 26;

  // A block of `n` bytes (kMin <= n <= kMax), or nullptr when malloc fails.
  void* take(std::size_t n) {
    void* p = nullptr;
    const std::size_t size = std::bit_ceil(n);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      int best = -1;
      for (int i = 0; i < kept_count_; ++i)
        if (kept_[i].size >= size && (best < 0 || kept_[i].size < kept_[best].size)) best = i;
      if (best >= 0) {
        p = kept_[best].p;
        kept_bytes_ -= kept_[best].size;
        kept_[best] = kept_[--kept_count_];
      }
    }
    if (p) {
      // ASan keeps a block's first allocation stack, so a leak of the block in its second life would be reported
      // against the first one's code, and the suppressions of the libraries' known leaks would miss it. A
      // reused block is left out of leak checks; a fresh one is checked as ever.
      __lsan_ignore_object(p);
    } else if (!(p = std::malloc(size))) {
      return nullptr;
    }
    __asan_unpoison_memory_region(p, n);
    __asan_poison_memory_region(static_cast<char*>(p) + n, __sanitizer_get_allocated_size(p) - n);
    return p;
  }

  // Keeps or frees `p` when it is one of take's blocks (true), else false: the caller frees it. `asked`: the size
  // the caller allocated, when it knows it (sized delete), else 0.
  bool give(void* p, std::size_t asked) {
    if (asked && asked < kMin) return false;
    const std::size_t size = __sanitizer_get_allocated_size(p);
    if (size < kMin || size > kMax || !std::has_single_bit(size)) return false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (kept_count_ < kSlots && kept_bytes_ + size <= kKeepBytes) {
        __asan_poison_memory_region(p, size);
        kept_[kept_count_++] = Block{p, size};
        kept_bytes_ += size;
        return true;
      }
    }
    __asan_unpoison_memory_region(p, size);
    std::free(p);
    return true;
  }

 private:
  struct Block {
    void* p = nullptr;
    std::size_t size = 0;
  };
  static constexpr int kSlots = 32;
  static constexpr std::size_t kKeepBytes = std::size_t{1} << 28;
  std::mutex mutex_;
  Block kept_[kSlots];
  int kept_count_ = 0;
  std::size_t kept_bytes_ = 0;
};

// Never destroyed: operator delete runs during and after static destruction.
inline LargeBlocks& large_blocks() {
  static LargeBlocks* blocks = new (std::malloc(sizeof(LargeBlocks))) LargeBlocks;
  return *blocks;
}
#endif

inline void* allocate(std::size_t n) noexcept {
  if (n > kMaxAllocation) return nullptr;
#if MV_REUSE_LARGE_BLOCKS
  if (n >= LargeBlocks::kMin && n <= LargeBlocks::kMax) return large_blocks().take(n);
#endif
  return std::malloc(n ? n : 1);
}

inline void release(void* p, std::size_t asked = 0) noexcept {
  if (!p) return;
#if MV_REUSE_LARGE_BLOCKS
  if (large_blocks().give(p, asked)) return;
#endif
  std::free(p);
}
}  // namespace mv::fuzz

void* operator new(std::size_t n) {
  if (void* p = mv::fuzz::allocate(n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return mv::fuzz::allocate(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return mv::fuzz::allocate(n); }
void operator delete(void* p) noexcept { mv::fuzz::release(p); }
void operator delete[](void* p) noexcept { mv::fuzz::release(p); }
void operator delete(void* p, std::size_t n) noexcept { mv::fuzz::release(p, n); }
void operator delete[](void* p, std::size_t n) noexcept { mv::fuzz::release(p, n); }
void operator delete(void* p, const std::nothrow_t&) noexcept { mv::fuzz::release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { mv::fuzz::release(p); }

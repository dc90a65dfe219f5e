// Large host arrays on transparent huge pages: a fresh 4 KiB page costs a fault on first touch (about a second
// per GiB on the VMs measured here, a third of that with 2 MiB pages), and a 100M-point build touches several
// GiB of fresh columns, codes and orders. Where THP is in "madvise" mode (Debian's default) the kernel only
// uses huge pages for ranges marked so.
#pragma once
#include <sys/mman.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <new>
#include <vector>

namespace mv {

// Marks the whole 2 MiB pages inside [p, p + bytes) for huge pages; a no-op for small ranges or where the
// kernel refuses.
inline void advise_huge_pages(const void* p, size_t bytes) {
  constexpr uintptr_t kHuge = uintptr_t{1} << 21;
  if (bytes < 4 * kHuge) return;
  const uintptr_t lo = (reinterpret_cast<uintptr_t>(p) + kHuge - 1) & ~(kHuge - 1);
  const uintptr_t hi = (reinterpret_cast<uintptr_t>(p) + bytes) & ~(kHuge - 1);
  if (hi > lo) ::madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
}

// Touches every page of fresh memory [p, p + bytes) from all cores. The first touch of a page is the costly part
// of fresh memory (the kernel zeroes it, and on a VM the hypervisor backs it): done by the one thread that fills
// a vector it takes several times longer than spread over the cores. Writes zeros, so call it only on storage
// that holds no values yet.
inline void prefault(void* p, size_t bytes) {
  constexpr size_t kPage = 4096;
  char* base = static_cast<char*>(p);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, (bytes + kPage - 1) / kPage, 512),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i < r.end(); ++i) static_cast<volatile char*>(base)[i * kPage] = 0;
                    });
}

// v.reserve(n) on fresh storage marked for huge pages before anything touches it (the elements move over after
// the mark: copied first, they would land on 4 KiB pages), and large storage touched from all cores (prefault)
// so that whoever fills it writes to memory that is already there.
template <class T>
void reserve_huge(std::vector<T>& v, size_t n) {
  if (n <= v.capacity()) return;
  std::vector<T> fresh;
  fresh.reserve(n);
  const size_t bytes = fresh.capacity() * sizeof(T);
  advise_huge_pages(fresh.data(), bytes);
  constexpr size_t kPrefaultFrom = size_t{64} << 20;
  if (bytes >= kPrefaultFrom) prefault(fresh.data(), bytes);
  fresh.insert(fresh.end(), std::make_move_iterator(v.begin()), std::make_move_iterator(v.end()));
  v.swap(fresh);
}

// An anonymous mapping aligned to 2 MiB and marked for huge pages before anything touches it: the storage of
// device memory that lives in host memory (an OpenCL CPU device's arenas). Unmapped on destruction.
class HugeBlock {
 public:
  explicit HugeBlock(size_t bytes) : bytes_(bytes) {
    constexpr size_t kHuge = size_t{1} << 21;
    const size_t mapped = bytes + kHuge;  // room to align the start
    void* p = ::mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    const uintptr_t lo = reinterpret_cast<uintptr_t>(p);
    const uintptr_t start = (lo + kHuge - 1) & ~uintptr_t{kHuge - 1};
    // Give back the slack before and after the aligned block.
    if (start > lo) ::munmap(p, start - lo);
    const size_t tail = (lo + mapped) - (start + bytes);
    if (tail) ::munmap(reinterpret_cast<void*>(start + bytes), tail);
    data_ = reinterpret_cast<void*>(start);
    advise_huge_pages(data_, bytes_);
  }
  ~HugeBlock() {
    if (data_) ::munmap(data_, bytes_);
  }
  HugeBlock(const HugeBlock&) = delete;
  HugeBlock& operator=(const HugeBlock&) = delete;
  void* data() const { return data_; }
  size_t size() const { return bytes_; }

 private:
  void* data_ = nullptr;
  size_t bytes_ = 0;
};

}  // namespace mv

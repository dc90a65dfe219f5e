// Large host arrays on transparent huge pages: a fresh 4 KiB page costs a fault on first touch (about a second
// per GiB on the VMs measured here, a third of that with 2 MiB pages), and a 100M-point build touches several
// GiB of fresh columns, codes and orders. Where THP is in "madvise" mode (Debian's default) the kernel only
// uses huge pages for ranges marked so.
#pragma once
#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
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

// v.reserve(n), the new storage marked for huge pages before anything touches it.
template <class T>
void reserve_huge(std::vector<T>& v, size_t n) {
  if (n <= v.capacity()) return;
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

}  // namespace mv

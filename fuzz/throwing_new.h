// Include in exactly one file of a fuzz target: replaces the plain operator new / delete with ones over
// malloc / free (so ASan still guards every block) whose allocations over 64 MiB throw std::bad_alloc. Under
// ASan a failed operator new aborts the process instead of throwing; this puts back what a real machine
// does, for targets whose third-party library allocates sizes read from the file before reading the data
// (the reader under test must turn that std::bad_alloc into an mv::Error). 64 MiB (no seed needs
// a tenth of that): OpenVDB copies a metadata record of a size the file declares several times over
// (fuzz/known/), and several such blocks at once below a limit near the 2 GiB RSS limit would still end in
// an out-of-memory. megavox's own huge allocations still stop the fuzzer,
// as a bad_alloc that escapes the reader (std::terminate) or as an out-of-memory.
// The sanitized test suite (tests/sanitizer_new.cpp) uses it with no limit (MV_THROWING_NEW_LIMIT 0): there
// only a malloc that fails (ASAN_OPTIONS=allocator_may_return_null=1) throws.
#pragma once
#include <cstdint>
#include <cstdlib>
#include <new>

namespace mv::fuzz {
#ifndef MV_THROWING_NEW_LIMIT
#define MV_THROWING_NEW_LIMIT (std::size_t{1} << 26)
#endif
inline constexpr std::size_t kMaxAllocation = MV_THROWING_NEW_LIMIT ? MV_THROWING_NEW_LIMIT : SIZE_MAX;
}

void* operator new(std::size_t n) {
  if (n > mv::fuzz::kMaxAllocation) throw std::bad_alloc();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  return n > mv::fuzz::kMaxAllocation ? nullptr : std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

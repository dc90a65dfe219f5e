// This process's peak resident set, and resetting it, for the benchmarks that report memory.
#pragma once
#include <sys/resource.h>

#include <cstdint>
#include <fstream>

namespace mv::bench {

// getrusage RUSAGE_SELF (Linux reports KiB): the device runtime's host memory included.
inline uint64_t peak_rss_bytes() {
  struct rusage u {};
  ::getrusage(RUSAGE_SELF, &u);
  return uint64_t(u.ru_maxrss) * 1024;
}

// Resets the peak to the current resident set (Linux 4.0+: "5" to /proc/self/clear_refs); false where it cannot.
inline bool reset_peak_rss() {
  std::ofstream f("/proc/self/clear_refs");
  if (!f) return false;
  f << "5";
  f.flush();
  return bool(f);
}

}  // namespace mv::bench

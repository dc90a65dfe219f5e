// A plain read of a file in 1 MiB blocks: what any tool reading that mesh pays at least, the build
// benchmarks' floor.
#pragma once
#include <cstdint>
#include <string>

namespace mv::bench {

struct PlainRead {
  uint64_t bytes = 0;
  double seconds = 0;
  double gb_per_s() const { return seconds > 0 ? double(bytes) / seconds / 1e9 : 0; }
};

// Throws mv::Error naming the file when it cannot be read.
PlainRead plain_read(const std::string& path);

}  // namespace mv::bench

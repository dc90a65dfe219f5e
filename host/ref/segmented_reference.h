// Plain loops for the segmented operations (host/core/megavox/segmented.h), for tests to compare against.
#pragma once
#include <cstdint>
#include <vector>

namespace mv::ref {

// The first element of each run of equal keys >> shift (shift 64 or more: one run), then n.
std::vector<uint32_t> segment_starts(const std::vector<uint64_t>& keys, uint32_t shift);

// Per run [starts[s], starts[s + 1]): the 64-bit sum of its values; per element the sum before it in its run;
// per run the position of its smallest value (the first of equals).
std::vector<uint64_t> segmented_sum(const std::vector<uint32_t>& values, const std::vector<uint32_t>& starts);
std::vector<uint64_t> segmented_exclusive_scan(const std::vector<uint32_t>& values, const std::vector<uint32_t>& starts);
std::vector<uint32_t> segmented_argmin(const std::vector<uint64_t>& values, const std::vector<uint32_t>& starts);

}  // namespace mv::ref

#include "segmented_reference.h"

#include <cstddef>

namespace mv::ref {

std::vector<uint32_t> segment_starts(const std::vector<uint64_t>& keys, uint32_t shift) {
  std::vector<uint32_t> starts;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const bool same = i > 0 && (shift >= 64 || (keys[i] >> shift) == (keys[i - 1] >> shift));
    if (!same) starts.push_back(static_cast<uint32_t>(i));
  }
  starts.push_back(static_cast<uint32_t>(keys.size()));
  return starts;
}

std::vector<uint64_t> segmented_sum(const std::vector<uint32_t>& values, const std::vector<uint32_t>& starts) {
  std::vector<uint64_t> sums;
  for (std::size_t s = 0; s + 1 < starts.size(); ++s) {
    uint64_t sum = 0;
    for (uint32_t i = starts[s]; i < starts[s + 1]; ++i) sum += values[i];
    sums.push_back(sum);
  }
  return sums;
}

std::vector<uint64_t> segmented_exclusive_scan(const std::vector<uint32_t>& values, const std::vector<uint32_t>& starts) {
  std::vector<uint64_t> out(values.size());
  for (std::size_t s = 0; s + 1 < starts.size(); ++s) {
    uint64_t sum = 0;
    for (uint32_t i = starts[s]; i < starts[s + 1]; ++i) {
      out[i] = sum;
      sum += values[i];
    }
  }
  return out;
}

std::vector<uint32_t> segmented_argmin(const std::vector<uint64_t>& values, const std::vector<uint32_t>& starts) {
  std::vector<uint32_t> out;
  for (std::size_t s = 0; s + 1 < starts.size(); ++s) {
    uint32_t best = starts[s];
    for (uint32_t i = starts[s] + 1; i < starts[s + 1]; ++i)
      if (values[i] < values[best]) best = i;
    out.push_back(best);
  }
  return out;
}

}  // namespace mv::ref

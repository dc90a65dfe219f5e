#include "reference.h"

namespace mv::ref {

uint64_t morton3(uint32_t x, uint32_t y, uint32_t z, int bits_per_axis) {
  uint64_t key = 0;
  for (int i = 0; i < bits_per_axis; ++i) {
    key |= uint64_t{(x >> i) & 1u} << (3 * i);
    key |= uint64_t{(y >> i) & 1u} << (3 * i + 1);
    key |= uint64_t{(z >> i) & 1u} << (3 * i + 2);
  }
  return key;
}

std::vector<uint32_t> exclusive_scan(const std::vector<uint32_t>& in) {
  std::vector<uint32_t> out(in.size() + 1, 0);
  for (size_t i = 0; i < in.size(); ++i) out[i + 1] = out[i] + in[i];
  return out;
}

}  // namespace mv::ref

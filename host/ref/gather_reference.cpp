#include "gather_reference.h"

#include <cstring>

namespace mv::ref {

std::vector<uint8_t> gather_records(std::span<const uint8_t> src, std::span<const uint32_t> index, uint32_t record_bytes) {
  std::vector<uint8_t> out(index.size() * record_bytes);
  for (size_t i = 0; i < index.size(); ++i)
    std::memcpy(out.data() + i * record_bytes, src.data() + uint64_t{index[i]} * record_bytes, record_bytes);
  return out;
}

std::array<int64_t, 6> point_bounds(std::span<const int32_t> xyz) {
  std::array<int64_t, 6> b{xyz[0], xyz[1], xyz[2], xyz[0], xyz[1], xyz[2]};
  for (size_t i = 0; i < xyz.size(); ++i) {
    const int a = static_cast<int>(i % 3);
    if (xyz[i] < b[a]) b[a] = xyz[i];
    if (xyz[i] > b[3 + a]) b[3 + a] = xyz[i];
  }
  return b;
}

}  // namespace mv::ref

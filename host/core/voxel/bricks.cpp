// Host side of 4^3 bricks (include/megavox/bricks.h): conversions from and to voxel keys, and OR-merges.
#include "megavox/bricks.h"

#include <bit>

#include "megavox/error.h"

namespace mv {

uint64_t Bricks::voxels() const {
  uint64_t n = 0;
  for (uint64_t m : masks) n += static_cast<uint64_t>(std::popcount(m));
  return n;
}

Bricks bricks_from_keys(std::span<const uint64_t> voxel_keys) {
  Bricks b;
  for (uint64_t k : voxel_keys) {
    const uint64_t key = k >> 6, bit = uint64_t{1} << (k & 63);
    if (!b.keys.empty() && b.keys.back() == key) {
      b.masks.back() |= bit;
      continue;
    }
    if (!b.keys.empty() && b.keys.back() > key) throw Error("voxel keys are not sorted");
    b.keys.push_back(key);
    b.masks.push_back(bit);
  }
  return b;
}

std::vector<uint64_t> keys_from_bricks(const Bricks& bricks) {
  std::vector<uint64_t> out;
  out.reserve(bricks.voxels());
  for (size_t i = 0; i < bricks.size(); ++i)
    for (uint64_t m = bricks.masks[i]; m; m &= m - 1)
      out.push_back(bricks.keys[i] << 6 | static_cast<uint64_t>(std::countr_zero(m)));
  return out;
}

void append_or_merged(std::span<const uint64_t> keys, std::span<const uint64_t> masks, Bricks& out) {
  for (size_t i = 0; i < keys.size(); ++i) {
    if (!out.keys.empty() && out.keys.back() == keys[i]) {
      out.masks.back() |= masks[i];
      continue;
    }
    out.keys.push_back(keys[i]);
    out.masks.push_back(masks[i]);
  }
}

Bricks merge_bricks(const Bricks& a, const Bricks& b) {
  Bricks out;
  out.keys.reserve(a.size() + b.size());
  out.masks.reserve(a.size() + b.size());
  size_t i = 0, j = 0;
  while (i < a.size() || j < b.size()) {
    const bool take_a = j == b.size() || (i < a.size() && a.keys[i] <= b.keys[j]);
    const uint64_t key = take_a ? a.keys[i] : b.keys[j];
    uint64_t mask = 0;
    if (i < a.size() && a.keys[i] == key) mask |= a.masks[i++];
    if (j < b.size() && b.keys[j] == key) mask |= b.masks[j++];
    out.keys.push_back(key);
    out.masks.push_back(mask);
  }
  out.keys.shrink_to_fit();
  out.masks.shrink_to_fit();
  return out;
}

}  // namespace mv

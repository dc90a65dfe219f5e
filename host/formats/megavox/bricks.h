// megavox — 4^3 voxel bricks: the bottom of the octree as the voxelizer emits it and the DAG build takes it.
// A brick is 64 voxels, its key the Morton key of its coordinates (= the voxel keys >> 6), its occupancy one
// 64-bit mask, bit i = the voxel at Morton index i inside it (so byte o is the 2^3 mask of octant o). A surface
// crosses a brick in about 16 voxels: one (key, mask) pair per brick moves 8x less than a key per voxel.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace mv {

struct Bricks {
  std::vector<uint64_t> keys;   // sorted, unique brick keys
  std::vector<uint64_t> masks;  // per key; never 0
  size_t size() const { return keys.size(); }
  bool empty() const { return keys.empty(); }
  uint64_t voxels() const;      // set bits over all masks
};

// The bricks of sorted, unique voxel keys.
Bricks bricks_from_keys(std::span<const uint64_t> voxel_keys);

// The sorted voxel keys of bricks.
std::vector<uint64_t> keys_from_bricks(const Bricks& bricks);

// Sorted keys with masks, repeats allowed (a brick met by several triangles): the distinct keys with their
// masks OR-ed, appended to `out` (whose keys must all be below keys[0] when out is not empty).
void append_or_merged(std::span<const uint64_t> keys, std::span<const uint64_t> masks, Bricks& out);

// The union of two brick sets (masks OR-ed where keys meet).
Bricks merge_bricks(const Bricks& a, const Bricks& b);

}  // namespace mv

// megavox — the DAG as plain data: levels of child masks and child ids (no device types).
//
// Levels count from the bottom (the convention of the public voxcom tools): level 0 = voxels, level 1 =
// 2x2x2 masks, level 2 = 4x4x4 bricks, ..., level L = the root of a 2^L grid. Octants are Morton octants
// (bit 0 = x, bit 1 = y, bit 2 = z); encoders convert to their format's order.
#pragma once
#include <cstdint>
#include <vector>

namespace mv {

// One level of a DAG, nodes in id order. Node i has child mask `mask[i]`; above level 1 its children's ids
// (into the level below) are children[first[i] .. first[i] + popcount(mask[i])), in octant order.
// In an SSVDAG, tags[j] is the reflection (bit 0 = x, 1 = y, 2 = z) on the pointer children[j]: that child
// subtree is the stored node mirrored across those axes (octant c becomes c ^ tag). Empty for an SVDAG.
struct DagLevel {
  std::vector<uint32_t> mask;
  std::vector<uint32_t> first;
  std::vector<uint32_t> children;
  std::vector<uint32_t> tags;
};

struct Dag {
  uint32_t levels = 0;              // L
  bool symmetric = false;           // SSVDAG: pointers carry reflection tags
  bool reduced = true;              // false: the plain octree (build_svo), every subtree stored once per use
  uint64_t voxels = 0;
  std::vector<uint64_t> svo_nodes;  // index = level: nodes of the sparse octree (level 0 = voxels)
  std::vector<DagLevel> level;      // index = level, 1..L (level[0] stays empty)
  uint64_t nodes(uint32_t l) const { return level[l].mask.size(); }
};

// Every voxel a DAG holds, as sorted Morton keys.
std::vector<uint64_t> decode_voxels(const Dag& dag);

}  // namespace mv

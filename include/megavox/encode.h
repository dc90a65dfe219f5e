// megavox — DAG encodings as stored in .mvx files.
//
// svdag: the thesis / SymVox 32-bit layout (Kaempe et al. 2013 as used by Jaspe Villanueva 2018), so sizes
// compare with the thesis's tables. A stream of 32-bit words, levels root first. An inner node is a header
// word (child mask in bits 0-7) followed by one 32-bit absolute word index per existing child, in descending
// child order; a level-1 node (2x2x2 leaf) is a single word holding its mask. Child order and mask bits use
// the thesis octant index c = 4x + 2y + z (megavox's own octants are Morton: x + 2y + 4z).
//
// ussvdag: the same layout for an SSVDAG; header bits 8-15, 16-23 and 24-31 are the X, Y and Z mirror bits
// of the pointer to child c (bit 8 + c, 16 + c, 24 + c): that child is the stored node mirrored across those
// axes. The root is stored in the model's orientation.
#pragma once
#include <cstdint>
#include <vector>

#include "megavox/dag.h"

namespace mv {

enum class Encoding : uint32_t { svdag = 2, ussvdag = 3 };

// Thesis octant index of a Morton octant (and back: the map is its own inverse).
constexpr uint32_t thesis_octant(uint32_t morton) { return ((morton & 1) << 2) | (morton & 2) | ((morton >> 2) & 1); }
uint32_t thesis_mask(uint32_t morton_mask);  // permutes mask bits the same way

struct EncodedDag {
  Encoding encoding = Encoding::svdag;
  uint32_t levels = 0;
  std::vector<uint32_t> words;         // the node stream
  std::vector<uint64_t> level_offset;  // index = level: first word of that level (levels root first)
};

// svdag for a plain DAG, ussvdag for a symmetric one.
EncodedDag encode_svdag(const Dag& dag);

// Checks the stream in one linear pass per level: node sizes tile each level, every pointer lands on a
// node start one level down (so no cycles), one root. Throws mv::Error naming the fault.
void validate_svdag(const EncodedDag& enc);

// Validates, then expands every path: the voxels as sorted Morton keys (memory grows with the voxels).
std::vector<uint64_t> decode_svdag(const EncodedDag& enc);

}  // namespace mv

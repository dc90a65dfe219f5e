// megavox — DAG encodings as stored in .mvx files.
//
// svdag: the thesis / SymVox 32-bit layout (Kaempe et al. 2013 as used by Jaspe Villanueva 2018), so sizes
// compare with the thesis's tables. A stream of 32-bit words, levels root first. An inner node is a header
// word (child mask in bits 0-7) followed by one 32-bit absolute word index per existing child, in descending
// child order; a level-1 node (2x2x2 leaf) is a single word holding its mask. Child order and mask bits use
// the x-major octant index c = 4x + 2y + z (megavox's own octants are Morton: x + 2y + 4z).
//
// ussvdag: the same layout for an SSVDAG; header bits 8-15, 16-23 and 24-31 are the X, Y and Z mirror bits
// of the pointer to child c (bit 8 + c, 16 + c, 24 + c): that child is the stored node mirrored across those
// axes. The root is stored in the model's orientation.
#pragma once
#include <cstdint>
#include <vector>

#include "megavox/dag_types.h"

namespace mv {

// ssvdag: the compact encoding of the thesis (Jaspe Villanueva 2018, 5.4; SymVox) for an SSVDAG. Level-2
// nodes become 64-bit 4x4x4 bricks (bit 16x + 4y + z, children already mirrored by their tags) in a brick
// array; the inner levels (L .. 3) are streams of 16-bit words, each level's nodes sorted by descending
// reference count so popular nodes get short offsets. A node is a header word (2 bits per child c = 0..7,
// x-major octants: 00 empty, 01 16-bit pointer, 10 / 11 32-bit pointer whose offset bit 29 is 0 / 1) and the
// pointers of its children in descending c. A 16-bit pointer holds the Z, Y, X mirror bits in bits 15..13
// and a 13-bit offset; a 32-bit pointer (high word first) the mirror bits in 31..29 and offset bits 28..0.
// Offsets count 16-bit words from the start of the child's level, or bricks when the child is a brick.
// svo: the plain octree (build_svo) in the svdag layout, each subtree stored once per use.
enum class Encoding : uint32_t { svo = 1, svdag = 2, ussvdag = 3, ssvdag = 4 };

struct EncodedDag {
  Encoding encoding = Encoding::svdag;
  uint32_t levels = 0;
  std::vector<uint32_t> words;         // svdag, ussvdag: the node stream
  std::vector<uint64_t> level_offset;  // index = level: first word of that level (levels root first)
  std::vector<uint16_t> inner;         // ssvdag: levels L .. 3, root first
  std::vector<uint64_t> bricks;        // ssvdag: level-2 nodes
  uint64_t bytes() const { return words.size() * 4 + inner.size() * 2 + bricks.size() * 8; }
};

// svdag for a plain DAG, ussvdag for a symmetric one, svo for an unreduced octree.
EncodedDag encode_svdag(const Dag& dag);

// The compact ssvdag encoding of an SSVDAG with at least 3 levels.
EncodedDag encode_ssvdag(const Dag& symmetric_dag);

// Checks the stream in one linear pass per level: node sizes tile each level, every pointer lands on a
// node start one level down (so no cycles), one root. Throws mv::Error naming the fault.
void validate_svdag(const EncodedDag& enc);
void validate_ssvdag(const EncodedDag& enc);

// Validates, then expands every path: the voxels as sorted Morton keys (memory grows with the voxels).
std::vector<uint64_t> decode_svdag(const EncodedDag& enc);
std::vector<uint64_t> decode_ssvdag(const EncodedDag& enc);

// The order of nodes in a paged node stream (host/formats/paging/page_layout.h, the paged .mvx): `level` keeps the
// stream's own order (levels root first), `subtree` clusters each page around a subtree.
enum class NodeOrder : uint32_t { level = 0, subtree = 1 };

// The octree nodes per level (index 0 = voxels .. levels = the root) of a validated encoding: every node counted
// once per path that reaches it, in one pass over the stream (saturating at 2^64 - 1). Empty for an empty DAG.
std::vector<uint64_t> encoded_octree_nodes_svdag(const EncodedDag& enc);
std::vector<uint64_t> encoded_octree_nodes(const EncodedDag& enc);

// The depth-first subtree size (octree nodes below and including it, voxels counted, every path once) of each
// node of a validated encoding, at its stream position: per 32-bit word for svo / svdag / ussvdag, per 16-bit
// word of the inner stream for an ssvdag; positions that start no node hold 0. The colour walk of a ray hit
// (kernels/common/trace_colour.h) reads them (saturating at 2^64 - 1).
std::vector<uint64_t> encoded_subtree_sizes(const EncodedDag& enc);

// Validates / decodes whichever encoding `enc` holds.
void validate_encoded(const EncodedDag& enc);
std::vector<uint64_t> decode_encoded(const EncodedDag& enc);

}  // namespace mv

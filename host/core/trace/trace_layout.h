// What the traversal kernel (kernels/common/trace_nodes.h) reads of an encoded DAG, shared by the device engine and
// the host build of the kernel, so both walk the same bytes.
#pragma once
#include <cstdint>
#include <vector>

#include "common/trace_types.h"
#include "megavox/colour_palette.h"
#include "megavox/encode.h"

namespace mv {

// The stream as 32-bit words: svo / svdag / ussvdag as stored; the ssvdag inner stream (16-bit words, two
// per 32-bit word, low half first) followed by one spare word (two words at least), as the kernel reads 16-bit
// words in pairs (mv_node_load).
std::vector<uint32_t> trace_words(const EncodedDag& dag);

// ssvdag: the bricks as 32-bit halves (low half first); empty for the other encodings.
std::vector<uint32_t> trace_bricks(const EncodedDag& dag);

// ssvdag: where each level starts in the inner stream (index = level); empty for the other encodings.
std::vector<uint32_t> trace_level_offsets(const EncodedDag& dag);

// What the hit colour walk (kernels/common/trace_colour.h) reads beside the node words: the level starts (index =
// level; ssvdag only, else zeros), then one 32-bit subtree size per stream position (encoded_subtree_sizes).
// Throws mv::Error when the DAG has 2^32 octree nodes or more (the walk's indices are 32-bit).
std::vector<uint32_t> trace_colour_meta(const EncodedDag& dag);

// Depth-first colours as the walk reads them (kernels/common/trace_colour.h, MV_COLOUR_HEAD): raw, one
// R | G << 8 | B << 16 word per entry of `rgb`, or, given `palette` (the same colours compressed), the palette.
// Throws mv::Error when a palette's bits pass 32-bit offsets.
std::vector<uint32_t> trace_colour_words(const std::vector<uint8_t>& rgb, const ColourPalette* palette = nullptr);

// Sets p.mode (the levels; rays from a buffer, hit records) and the ssvdag level starts the parameters carry.
void set_trace_levels(MvTraceParams& p, const EncodedDag& dag);

}  // namespace mv

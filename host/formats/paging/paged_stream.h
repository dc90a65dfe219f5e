// The paged node stream: a 32-bit word encoding (svo, svdag, ussvdag) with its nodes moved to a
// PageLayout's words, as the paged .mvx stores it and the page cache uploads it page by page, and the way back
// to a level-order stream, which every resident consumer (render, export, info, interop) reads unchanged.
// The header words stay; the pointers depend on the order:
//   level:   a pointer counts words from the start of its child's level in the paged stream, and level_offset
//            holds those starts (index = level, 64-bit), so only each level must stay under 2^32 words;
//   subtree: a page mixes levels, so a pointer is the child's absolute word and the stream stays under 2^32
//            words; level_offset is empty.
#pragma once
#include <cstdint>

#include "paging/page_layout.h"
#include "megavox/encode.h"

namespace mv {

// The words of `enc` placed at layout.at, every child pointer rewritten to its child's new place (as the order
// says, above), padding words 0, the root at word 0. Same encoding and levels. Throws mv::Error when `layout` was
// not made for `enc` (nodes overlapping or missing), or a pointer does not fit its 32 bits.
EncodedDag paged_stream(const EncodedDag& enc, const PageLayout& layout);

// A valid level-order stream of the same DAG (passes validate_svdag, decodes to the same voxels; as many
// words as the unpaged stream), discovered from the root level by level: within a level, nodes keep the order
// in which their parents' pointers first reach them (parents in stream order, each one's children by
// ascending Morton octant), so a stream already in that order comes back byte for byte. Checks as it goes:
// every node header is one of its level, no node crosses a page boundary or overlaps another, every pointer
// lands on a node start inside the stream reached at one level only, and every word no node holds is zero
// padding. Throws mv::Error naming the word otherwise; reads nothing out of bounds, and its memory is bounded
// by the input's size whatever the input holds. `paged.level_offset` non-empty: the pointers count from those
// level starts (level order), and each child must lie inside its level.
EncodedDag level_order_stream(const EncodedDag& paged, uint32_t page_words);

}  // namespace mv

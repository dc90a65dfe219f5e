// The paged ssvdag: the compact encoding's 64-bit bricks and 16-bit inner nodes in one stream of
// 32-bit words, cut into pages of page_words words with every node inside one page, as the paged .mvx stores
// it and the page cache uploads it page by page; and the way back to the resident encoding.
//
// The pointer formats stay (include/megavox/encode.h): 16- or 32-bit pointers with mirror tags, offsets from
// the start of the child's level. What changes is where things lie:
//  - the levels: bricks first (2 words each, low half first), then the inner levels from 3 up to the root
//    (16-bit words, two per 32-bit word, low half first). Laid out bottom-up, a level's place in the stream is
//    known before the level above it is encoded, so the padding that keeps a node out of the next page (zero
//    words) is placed once, and an offset that grows past 13 bits with it simply takes a 32-bit pointer;
//  - the nodes of a level: those the resident encoding reaches with 13-bit offsets (its most referenced, which
//    it sorts first) stay first, in its order; the rest follow in the order a walk from the root first meets
//    them (level by level, children by ascending Morton octant), so a page holds neighbours in space, where the
//    resident order (by reference count) scatters them over the level.
// The way back recomputes the resident order from the structure alone (reference counts, ties by that first-met
// order: encode_ssvdag's rule), so it needs no stored permutation.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "megavox/encode.h"

namespace mv {

struct PagedSsvdag {
  std::vector<uint32_t> words;   // the paged stream (its last page not padded)
  std::vector<uint64_t> starts;  // levels + 1 entries: [0] 0, [1] the brick count, [2] the bricks' first
                                 // 32-bit word (0), [3 .. levels] each inner level's first node (16-bit words)
  std::vector<uint64_t> level_offset;  // of the resident encoding the way back gives (the input's, when
                                       // encode_ssvdag made it)
};

// The paged stream of a valid ssvdag (validated first); an empty DAG gives no words. Throws mv::Error for a
// page that cannot hold the largest node (17 16-bit words) or a stream past 2^31 words.
PagedSsvdag paged_ssvdag(const EncodedDag& enc, uint32_t page_words);

// The resident ssvdag of a paged stream: byte for byte the one paged_ssvdag was given when encode_ssvdag made it
// (another ssvdag of the same DAG comes back in encode_ssvdag's order, PagedSsvdag::level_offset). Checks as it goes:
// the starts tile the stream in order, every node lies inside its level and one page, every word no node
// holds is zero padding before a page boundary, every pointer lands on a brick or a node start of the level
// below, one root; then validate_ssvdag. Throws mv::Error naming the word otherwise; reads nothing out of
// bounds, and its memory is bounded by the input's size.
EncodedDag ssvdag_from_pages(std::span<const uint32_t> words, std::span<const uint64_t> starts, uint32_t levels,
                             uint32_t page_words);

}  // namespace mv

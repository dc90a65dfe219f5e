// The subtree sizes a paged stream's colour walk reads (kernels/common/trace_colour_paged.h): a plane beside the
// node pages, page for page, that holds at each child pointer the subtree size of the child it points to (its
// octree nodes, itself included: what a depth-first colour index skips over). Kept at the pointer, not at the
// child, so that a walk from the root to a hit reads only the pages on its own path: an earlier sibling's size
// is in its parent's page, the sibling's page may be anywhere.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "megavox/encode.h"

namespace mv {

// Plane words per stream word: one for the 32-bit word encodings (a size at each pointer word), two for an
// ssvdag (a size at each 16-bit word of its inner nodes; pointers start at any of them).
inline uint32_t size_plane_words(Encoding e) { return e == Encoding::ssvdag ? 2u : 1u; }

// The plane of a valid paged stream (paged_stream.h: svo / svdag / ussvdag, `starts` empty for absolute
// pointers; paged_ssvdag.h: an ssvdag and its starts): size_plane_words(e) words per stream word, zero where no
// pointer starts. Throws mv::Error when a subtree holds 2^32 octree nodes or more (colour indices are 32-bit).
std::vector<uint32_t> paged_size_plane(Encoding e, uint32_t levels, std::span<const uint32_t> words,
                                       std::span<const uint64_t> starts);

}  // namespace mv

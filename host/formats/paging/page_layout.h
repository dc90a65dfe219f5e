// Node orders for paging a DAG's node stream: which nodes share a page, so a ray's path touches few pages.
// A page is page_words consecutive words of the stream and every node lies in exactly one page: a node that
// would cross a page boundary starts the next page (the words skipped are padding). Two orders:
//   level:   today's stream order (levels root first), so the encoding is unchanged; a descent meets a new
//            page at nearly every level;
//   subtree: pages filled by breadth-first walks of subtrees: a page starts at a subtree root and takes its
//            descendants level by level until full; the frontier left over roots the next pages, and a walk
//            that ends before its page is full lets the next root continue that page. A DAG node shared by
//            several parents lives where the first walk meets it.
// 32-bit word encodings (svo, svdag, ussvdag); the ssvdag has its own layout (paged_ssvdag.h).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/encode.h"

namespace mv {

// The largest node of a 32-bit word encoding, in words: a header and eight pointers. A page holds at least one.
constexpr uint32_t kMaxNodeWords = 9;

// NodeOrder (level, subtree) is in megavox/encode.h: the paged .mvx stores it.
std::string node_order_name(NodeOrder o);

// Where every node goes: node k (in stream order) starts at word `at[k]` of the paged stream, in page
// at[k] / page_words.
struct PageLayout {
  NodeOrder order = NodeOrder::level;
  uint32_t page_words = 0;
  std::vector<uint32_t> old_at;  // node k's word in the encoding's own stream (ascending)
  std::vector<uint64_t> at;      // node k's word in the paged stream
  uint64_t words = 0;            // of the paged stream, padding included (the last page not padded)
  uint64_t pages() const { return (words + page_words - 1) / page_words; }
};

// Throws mv::Error for an ssvdag (paged_ssvdag.h) or a page smaller than the largest node (9 words). Validates
// the stream first.
PageLayout page_layout(const EncodedDag& enc, NodeOrder order, uint32_t page_words);

struct PageLayoutStats {
  uint64_t nodes = 0, words = 0, paged_words = 0, pages = 0;
  double size_ratio = 0;      // paged words / words
  uint64_t pointers = 0;      // child pointers
  uint64_t crossing = 0;      // pointers whose child is in another page than its parent
  double pages_per_path = 0;  // distinct pages a root-to-leaf descent reads, mean over the sampled paths
  uint32_t max_pages_per_path = 0;
  uint32_t levels = 0;        // nodes on every such path
};

// `paths` descents from the root, each picking one of the node's children uniformly at random (seeded, so the
// same paths for every layout of one DAG).
PageLayoutStats measure_page_layout(const EncodedDag& enc, const PageLayout& layout, uint32_t paths, uint64_t seed);

}  // namespace mv

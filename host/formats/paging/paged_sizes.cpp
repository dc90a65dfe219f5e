#include "paging/paged_sizes.h"

#include <string>

#include "common/trace_colour.h"
#include "megavox/error.h"

namespace mv {
namespace {

constexpr uint64_t kMaxSize = UINT32_MAX;

// Depth-first over the DAG with every node's size memoised by its position (a node shared by many parents is
// summed once); the depth is the level count, at most 21.
struct WordSizes {
  std::span<const uint32_t> in;
  std::span<const uint64_t> starts;  // empty: absolute pointers
  std::vector<uint32_t> plane, memo;

  uint64_t size(uint64_t w, uint32_t l) {
    if (w >= in.size()) throw Error("size plane: a pointer past the stream");
    if (l == 1) return 1 + __builtin_popcount(in[w] & 0xffu);
    if (memo[w]) return memo[w];
    const uint32_t header = in[w];
    uint64_t total = 1;
    for (uint32_t t8 = 0; t8 < 8; ++t8) {
      if (!(header >> t8 & 1)) continue;
      const uint64_t at = w + mv_word_child_at(0, header, t8);  // (w may pass 2^32: the offset alone)
      if (at >= in.size()) throw Error("size plane: a node past the stream");
      const uint64_t child = (starts.empty() ? 0 : starts[l - 1]) + in[at];
      const uint64_t s = size(child, l - 1);
      plane[at] = static_cast<uint32_t>(s);
      total += s;
    }
    if (total > kMaxSize) throw Error("size plane: a subtree of 2^32 octree nodes or more");
    memo[w] = static_cast<uint32_t>(total);
    return total;
  }
};

// The same over a paged ssvdag: inner nodes at 16-bit positions (starts[l] for level l >= 3), bricks at 32-bit
// words 2b and 2b + 1; the plane holds a size per 16-bit position.
struct CompactSizes {
  std::span<const uint32_t> in;
  std::span<const uint64_t> starts;
  std::vector<uint32_t> plane, memo;

  uint32_t half(uint64_t h) const {
    if (h / 2 >= in.size()) throw Error("size plane: a pointer past the stream");
    return (in[h / 2] >> (16 * (h & 1))) & 0xffffu;
  }
  uint64_t size(uint64_t h, uint32_t l) {  // l >= 3: h a 16-bit position; l == 2: h a brick
    if (l == 2) {
      if (2 * h + 1 >= in.size()) throw Error("size plane: a brick past the stream");
      return mv_brick_size(in[2 * h], in[2 * h + 1]);
    }
    if (memo[h]) return memo[h];
    const uint32_t header = half(h);
    uint64_t total = 1;
    for (uint32_t t8 = 0; t8 < 8; ++t8) {
      const uint32_t code = mv_ssvdag_child_code(header, t8);
      if (code == 0) continue;
      const uint32_t rel = mv_ssvdag_child_at(0, header, t8);  // pointers follow the header in 16-bit words
      const uint64_t at = h + rel;
      const uint32_t off = mv_ssvdag_offset(half(at) | (code == 1 ? 0u : half(at + 1) << 16), code);
      const uint64_t s = size(l - 1 == 2 ? off : starts[l - 1] + off, l - 1);
      plane[at] = static_cast<uint32_t>(s);
      total += s;
    }
    if (total > kMaxSize) throw Error("size plane: a subtree of 2^32 octree nodes or more");
    memo[h] = static_cast<uint32_t>(total);
    return total;
  }
};

}  // namespace

std::vector<uint32_t> paged_size_plane(Encoding e, uint32_t levels, std::span<const uint32_t> words,
                                       std::span<const uint64_t> starts) {
  if (words.empty() || levels == 0) return {};
  if (!starts.empty() && starts.size() != levels + 1u) throw Error("size plane: level starts for another DAG");
  if (e == Encoding::ssvdag) {
    if (levels < 3 || starts.empty()) throw Error("size plane: an ssvdag needs 3 levels and its level starts");
    CompactSizes c{words, starts, std::vector<uint32_t>(2 * words.size(), 0), std::vector<uint32_t>(2 * words.size(), 0)};
    c.size(starts[levels], levels);
    return std::move(c.plane);
  }
  WordSizes w{words, starts, std::vector<uint32_t>(words.size(), 0), std::vector<uint32_t>(words.size(), 0)};
  w.size(starts.empty() ? 0 : starts[levels], levels);
  return std::move(w.plane);
}

}  // namespace mv

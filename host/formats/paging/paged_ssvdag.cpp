#include "paging/paged_ssvdag.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "common/trace_nodes.h"
#include "encode/node_order.h"
#include "megavox/error.h"

namespace mv {
namespace {

constexpr uint32_t kMaxNodeWords16 = 17;  // a header and eight 32-bit pointers, in 16-bit words
constexpr uint64_t kMaxOffset = uint64_t{1} << 30;

// One inner level's nodes in stream order; node k's children (descending x-major octant, the pointers' order)
// are [first[k], first[k + 1]): the node or brick each points to (its index in the level below) and its tag.
struct Level {
  std::vector<uint32_t> first{0};
  std::vector<uint32_t> target;
  std::vector<uint8_t> octant, tag;
  uint32_t nodes() const { return static_cast<uint32_t>(first.size() - 1); }
};

Error fail(const std::string& why) { return Error("ssvdag pages: " + why); }

// The nodes of inner level `l` in 16-bit words in[begin, end) (absolute indices). `below`: the starts of the
// level below's nodes, relative to its begin, ascending (level 3: null, and `bricks` bricks). page16 != 0:
// zero padding may run from a node's end to the next multiple of page16 (or to the level's end, when the next
// level starts there), and no node crosses such a multiple. `root`: the level holds one node, and at most one
// zero word follows it. Returns the level's node starts relative to begin.
std::vector<uint64_t> parse_level(std::span<const uint16_t> in, uint64_t begin, uint64_t end, uint64_t page16,
                                  uint32_t l, const std::vector<uint64_t>* below, uint64_t bricks, bool root,
                                  Level& out) {
  std::vector<uint64_t> starts;
  for (uint64_t w = begin; w < end;) {
    if (root && !starts.empty()) {
      if (end - w > 1 || in[w] != 0) throw fail("16-bit word " + std::to_string(w) + " follows the root");
      break;
    }
    const uint32_t header = in[w];
    if (header == 0) {
      const uint64_t boundary = page16 ? (w / page16 + 1) * page16 : w + 1;
      if (page16 == 0 || boundary > end)
        throw fail("16-bit word " + std::to_string(w) + " of level " + std::to_string(l) + " is an empty node");
      for (; w < boundary; ++w)
        if (in[w] != 0) throw fail("16-bit word " + std::to_string(w) + " lies in padding but is not zero");
      continue;
    }
    uint64_t size = 1;
    for (uint32_t t = 0; t < 8; ++t) size += std::min<uint32_t>(header >> (2 * t) & 3, 2);
    if (w + size > end)
      throw fail("the node at 16-bit word " + std::to_string(w) + " runs past level " + std::to_string(l));
    if (page16 && w / page16 != (w + size - 1) / page16)
      throw fail("the node at 16-bit word " + std::to_string(w) + " crosses a page boundary");
    starts.push_back(w - begin);
    uint64_t q = w + 1;
    for (int t = 7; t >= 0; --t) {
      const uint32_t code = header >> (2 * t) & 3;
      if (code == 0) continue;
      const uint32_t hi = in[q++];
      uint64_t off;
      uint32_t tag;
      if (code == 1) {
        off = hi & 0x1fffu;
        tag = hi >> 13;
      } else {
        const uint32_t word = hi << 16 | in[q++];
        off = (word & 0x1fffffffu) | uint64_t{code & 1} << 29;
        tag = word >> 29;
      }
      uint64_t target = off;
      if (below) {
        const auto at = std::lower_bound(below->begin(), below->end(), off);
        if (at == below->end() || *at != off)
          throw fail("the node at 16-bit word " + std::to_string(w) + " points to no node of level " +
                     std::to_string(l - 1));
        target = static_cast<uint64_t>(at - below->begin());
      } else if (off >= bricks) {
        throw fail("the node at 16-bit word " + std::to_string(w) + " points past the bricks");
      }
      out.target.push_back(static_cast<uint32_t>(target));
      out.octant.push_back(static_cast<uint8_t>(t));
      out.tag.push_back(static_cast<uint8_t>(tag));
    }
    out.first.push_back(static_cast<uint32_t>(out.target.size()));
    w += size;
  }
  if (starts.empty()) throw fail("level " + std::to_string(l) + " holds no node");
  return starts;
}

// Appends level `lv` to `out`, whose word out.size() lies at 16-bit word `at` of the whole stream: each node's
// pointers take the offsets below_rel gives their targets (null: the target is the offset, bricks), codes by
// the encoder's rule (13 bits fit: 16-bit pointer). page16 != 0: zero padding keeps every node inside a page.
// Returns each node's offset from the level's start.
std::vector<uint64_t> emit_level(const Level& lv, const std::vector<uint64_t>* below_rel, uint64_t at, uint64_t page16,
                                 std::vector<uint16_t>& out) {
  const uint64_t begin = out.size();
  std::vector<uint64_t> rel(lv.nodes());
  for (uint32_t k = 0; k < lv.nodes(); ++k) {
    uint32_t header = 0;
    uint64_t size = 1;
    for (uint32_t j = lv.first[k]; j < lv.first[k + 1]; ++j) {
      const uint64_t off = below_rel ? (*below_rel)[lv.target[j]] : lv.target[j];
      if (off >= kMaxOffset) throw Error("ssvdag: an offset needs more than 30 bits");
      const uint32_t code = off < (1u << 13) ? 1 : 2 + static_cast<uint32_t>(off >> 29 & 1);
      header |= code << (2 * lv.octant[j]);
      size += std::min<uint32_t>(code, 2);
    }
    const uint64_t pos = at + (out.size() - begin);
    if (page16 && pos % page16 + size > page16) out.resize(out.size() + page16 - pos % page16, 0);
    rel[k] = out.size() - begin;
    out.push_back(static_cast<uint16_t>(header));
    for (uint32_t j = lv.first[k]; j < lv.first[k + 1]; ++j) {
      const uint64_t off = below_rel ? (*below_rel)[lv.target[j]] : lv.target[j];
      const uint32_t mirror = uint32_t{lv.tag[j]} << 13;
      if (off < (1u << 13)) {
        out.push_back(static_cast<uint16_t>(mirror | off));
      } else {
        const uint32_t word = mirror << 16 | static_cast<uint32_t>(off & 0x1fffffffu);
        out.push_back(static_cast<uint16_t>(word >> 16));
        out.push_back(static_cast<uint16_t>(word & 0xffffu));
      }
    }
  }
  return rel;
}

// An ssvdag as node lists: level[l] for the inner levels 3 .. L, and the bricks (level 2).
struct Parsed {
  std::vector<Level> level;
  std::vector<uint64_t> bricks;
};

// The node-order callbacks (encode/node_order.h) over `in`: children carry x-major octants, Morton is their image.
struct Shape {
  const Parsed& in;
  uint32_t operator()(uint32_t l) const {
    return l == 2 ? static_cast<uint32_t>(in.bricks.size()) : in.level[l].nodes();
  }
  template <class F>
  void operator()(uint32_t l, uint32_t k, F&& f) const {
    const Level& lv = in.level[l];
    for (uint32_t j = lv.first[k]; j < lv.first[k + 1]; ++j) f(mv_xmajor_octant(lv.octant[j]), lv.target[j]);
  }
};

// `in` with its nodes placed in `order` (order[l][p]: the node of `in` that goes p-th), pointers following.
Parsed reorder(const Parsed& in, const std::vector<std::vector<uint32_t>>& order, uint32_t L) {
  Parsed out;
  out.level.resize(L + 1);
  out.bricks.resize(in.bricks.size());
  std::vector<uint32_t> below(in.bricks.size());  // new place of each node of the level below
  for (uint32_t p = 0; p < order[2].size(); ++p) {
    out.bricks[p] = in.bricks[order[2][p]];
    below[order[2][p]] = p;
  }
  for (uint32_t l = 3; l <= L; ++l) {
    const Level& a = in.level[l];
    Level& b = out.level[l];
    std::vector<uint32_t> here(a.nodes());
    for (uint32_t p = 0; p < order[l].size(); ++p) {
      const uint32_t k = order[l][p];
      here[k] = p;
      for (uint32_t j = a.first[k]; j < a.first[k + 1]; ++j) {
        b.target.push_back(below[a.target[j]]);
        b.octant.push_back(a.octant[j]);
        b.tag.push_back(a.tag[j]);
      }
      b.first.push_back(static_cast<uint32_t>(b.target.size()));
    }
    below.swap(here);
  }
  return out;
}

// The resident encoding of `in`, its nodes in the order given.
EncodedDag resident(const Parsed& in, uint32_t L) {
  EncodedDag enc;
  enc.encoding = Encoding::ssvdag;
  enc.levels = L;
  enc.level_offset.assign(L + 1, 0);
  enc.bricks = in.bricks;
  std::vector<std::vector<uint16_t>> streams(L + 1);
  std::vector<uint64_t> rel;
  for (uint32_t l = 3; l <= L; ++l) rel = emit_level(in.level[l], l == 3 ? nullptr : &rel, 0, 0, streams[l]);
  for (uint32_t l = L; l >= 3; --l) {
    enc.level_offset[l] = enc.inner.size();
    enc.inner.insert(enc.inner.end(), streams[l].begin(), streams[l].end());
  }
  return enc;
}

}  // namespace

PagedSsvdag paged_ssvdag(const EncodedDag& enc, uint32_t page_words) {
  if (enc.encoding != Encoding::ssvdag) throw Error("paged ssvdag: the DAG is not an ssvdag");
  if (2 * uint64_t{page_words} < kMaxNodeWords16 || page_words % 2)
    throw fail("pages of " + std::to_string(page_words) + " words cannot hold a node");
  validate_ssvdag(enc);
  PagedSsvdag out;
  const uint32_t L = enc.levels;
  out.starts.assign(L + 1, 0);
  out.level_offset = enc.level_offset;
  if (enc.inner.empty()) return out;
  const uint64_t page16 = uint64_t{page_words} * 2;
  // The levels as node lists, bottom-up (each needs the starts of the one below), in the resident order.
  Parsed parsed;
  parsed.level.resize(L + 1);
  parsed.bricks = enc.bricks;
  std::vector<uint64_t> below;
  for (uint32_t l = 3; l <= L; ++l) {
    const uint64_t end = l == 3 ? enc.inner.size() : enc.level_offset[l - 1];
    below = parse_level(enc.inner, enc.level_offset[l], end, 0, l, l == 3 ? nullptr : &below, enc.bricks.size(), l == L,
                        parsed.level[l]);
  }
  // the input itself, if encode_ssvdag made it
  const Parsed canon = reorder(parsed, resident_node_order(L, Shape{parsed}, Shape{parsed}), L);
  const EncodedDag res = resident(canon, L);
  out.level_offset = res.level_offset;
  // The paged order of each level: the nodes the resident encoding reaches with 13-bit offsets (the most
  // referenced) first, as there, then the rest in first-met order, so that a page holds neighbours in space.
  const std::vector<std::vector<uint32_t>> met = first_met_order(L, Shape{canon}, Shape{canon});
  std::vector<std::vector<uint32_t>> order(L + 1);
  for (uint32_t l = 2; l <= L; ++l) {
    uint32_t head = 0;  // resident nodes at offsets under 2^13 (positions, as canon is in resident order)
    if (l == 2) {
      head = static_cast<uint32_t>(std::min<uint64_t>(canon.bricks.size(), 1u << 13));
    } else {
      const uint64_t end = l == 3 ? res.inner.size() : res.level_offset[l - 1];
      for (uint64_t w = res.level_offset[l]; w < end && w - res.level_offset[l] < (1u << 13); ++head) {
        uint64_t size = 1;
        for (uint32_t t = 0; t < 8; ++t) size += std::min<uint32_t>(res.inner[w] >> (2 * t) & 3, 2);
        w += size;
      }
    }
    for (uint32_t p = 0; p < head; ++p) order[l].push_back(p);
    for (uint32_t k : met[l])
      if (k >= head) order[l].push_back(k);
  }
  const Parsed paged = reorder(canon, order, L);
  std::vector<uint16_t> all(paged.bricks.size() * 4);
  std::memcpy(all.data(), paged.bricks.data(), paged.bricks.size() * 8);  // little-endian: low half first
  out.starts[1] = paged.bricks.size();
  std::vector<uint64_t> rel;
  for (uint32_t l = 3; l <= L; ++l) {
    const uint64_t at = all.size();
    rel = emit_level(paged.level[l], l == 3 ? nullptr : &rel, at, page16, all);
    // padding before a level's first node belongs to the end of the level below: offsets count from the node
    const uint64_t pad = rel.front();
    for (uint64_t& r : rel) r -= pad;
    out.starts[l] = at + pad;
  }
  if (all.size() % 2) all.push_back(0);
  if (all.size() / 2 >= (uint64_t{1} << 31)) throw fail(std::to_string(all.size() / 2) + " words exceed 2^31");
  out.words.resize(all.size() / 2);
  std::memcpy(out.words.data(), all.data(), all.size() * 2);
  return out;
}

EncodedDag ssvdag_from_pages(std::span<const uint32_t> words, std::span<const uint64_t> starts, uint32_t L,
                             uint32_t page_words) {
  EncodedDag enc;
  enc.encoding = Encoding::ssvdag;
  enc.levels = L;
  if (L < 3 || L > 21) throw fail("bad level count " + std::to_string(L));
  enc.level_offset.assign(L + 1, 0);
  if (words.empty()) return enc;
  if (2 * uint64_t{page_words} < kMaxNodeWords16 || page_words % 2)
    throw fail("pages of " + std::to_string(page_words) + " words cannot hold a node");
  if (starts.size() != L + 1u)
    throw fail(std::to_string(starts.size()) + " level starts for " + std::to_string(L) + " levels");
  const uint64_t n16 = uint64_t{words.size()} * 2;
  if (starts[0] || starts[2]) throw fail("the bricks must start at word 0");
  for (uint32_t l = 3; l <= L; ++l)
    if (starts[l] > n16 || (l > 3 && starts[l] <= starts[l - 1]))
      throw fail("level " + std::to_string(l) + " starts at 16-bit word " + std::to_string(starts[l]) +
                 ", out of order");
  const uint64_t bricks = starts[1];
  const uint64_t page16 = uint64_t{page_words} * 2;
  const std::span<const uint16_t> in(reinterpret_cast<const uint16_t*>(words.data()), n16);
  // between the bricks and level 3: nothing, or zero padding up to a page boundary
  if (bricks > starts[3] / 4 || (starts[3] != bricks * 4 && starts[3] % page16 != 0))
    throw fail(std::to_string(bricks) + " bricks do not end where level 3 starts (16-bit word " +
               std::to_string(starts[3]) + ")");
  for (uint64_t w = bricks * 4; w < starts[3]; ++w)
    if (in[w] != 0) throw fail("16-bit word " + std::to_string(w) + " lies in padding but is not zero");
  // Levels bottom-up; padding before a level's first node lies at the end of the level below.
  Parsed paged;
  paged.level.resize(L + 1);
  std::vector<uint64_t> below;
  for (uint32_t l = 3; l <= L; ++l) {
    const uint64_t end = l == L ? n16 : starts[l + 1];
    below = parse_level(in, starts[l], end, page16, l, l == 3 ? nullptr : &below, bricks, l == L, paged.level[l]);
    if (below.front() != 0) throw fail("level " + std::to_string(l) + " does not start with a node");
  }
  paged.bricks.resize(bricks);
  std::memcpy(paged.bricks.data(), words.data(), bricks * 8);
  enc = resident(reorder(paged, resident_node_order(L, Shape{paged}, Shape{paged}), L), L);
  validate_ssvdag(enc);
  return enc;
}

}  // namespace mv

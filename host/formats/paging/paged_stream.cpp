#include "paging/paged_stream.h"

#include <algorithm>
#include <string>
#include <vector>

#include "common/trace_nodes.h"
#include "megavox/error.h"

namespace mv {
namespace {

uint32_t node_words(uint32_t header, uint32_t level) { return level == 1 ? 1 : 1 + __builtin_popcount(header & 0xffu); }

// The word of child `c` (a Morton octant present in the header's mask) among the node's pointers, which are
// stored in descending x-major octant order.
uint32_t pointer_of(uint32_t header, uint32_t c) {
  const uint32_t t = mv_xmajor_octant(c);
  return 1 + __builtin_popcount(header & 0xffu & ~((2u << t) - 1));
}

}  // namespace

EncodedDag paged_stream(const EncodedDag& enc, const PageLayout& lay) {
  if (enc.encoding == Encoding::ssvdag) throw Error("paged stream: svo, svdag and ussvdag only (an ssvdag: paged_ssvdag.h)");
  EncodedDag out;
  out.encoding = enc.encoding;
  out.levels = enc.levels;
  if (enc.words.empty()) return out;
  auto fail = [](const std::string& why) { return Error("paged stream: the layout does not fit the DAG: " + why); };
  if (lay.at.size() != lay.old_at.size() || lay.page_words < kMaxNodeWords) throw fail("bad layout");
  const bool relative = lay.order == NodeOrder::level;
  if (!relative && lay.words > UINT32_MAX)
    throw Error("paged stream: " + std::to_string(lay.words) + " words in subtree order exceed 32-bit pointers");
  if (enc.level_offset.size() != enc.levels + 1u) throw fail("bad level offsets");
  // Each node's new word by its old one (a pointer is resolved in one load, not a search).
  constexpr uint64_t kNone = UINT64_MAX;
  std::vector<uint64_t> moved(enc.words.size(), kNone);
  for (size_t j = 0; j < lay.old_at.size(); ++j)
    if (lay.old_at[j] < moved.size()) moved[lay.old_at[j]] = lay.at[j];
  out.words.assign(lay.words, 0);
  if (relative) {  // each level's first node is where its level starts (level order keeps the stream's order)
    out.level_offset.assign(enc.levels + 1u, 0);
    for (uint32_t l = 1; l <= enc.levels; ++l) {
      const uint64_t first = enc.level_offset[l];
      if (first >= moved.size() || moved[first] == kNone) throw fail("level " + std::to_string(l) + " has no node");
      out.level_offset[l] = moved[first];
    }
  }
  std::vector<bool> used(lay.words, false);  // so that overlapping nodes (one placed twice, one never) are caught
  size_t k = 0;
  for (uint32_t l = enc.levels; l >= 1; --l) {
    const uint64_t end = l == 1 ? enc.words.size() : enc.level_offset[l - 1];
    if (end > enc.words.size()) throw fail("bad level offsets");
    const uint64_t base = relative && l > 1 ? out.level_offset[l - 1] : 0;  // where the children's level starts
    for (uint64_t w = enc.level_offset[l]; w < end; ++k) {
      if (k >= lay.old_at.size() || lay.old_at[k] != w) throw fail("node " + std::to_string(k) + " is elsewhere");
      const uint32_t size = node_words(enc.words[w], l);
      if (w + size > end) throw fail("node " + std::to_string(k) + " runs past its level");
      const uint64_t at = lay.at[k];
      if (at + size > lay.words || at / lay.page_words != (at + size - 1) / lay.page_words)
        throw fail("node " + std::to_string(k) + " leaves its page");
      for (uint64_t q = 0; q < size; ++q) {
        if (used[at + q]) throw fail("node " + std::to_string(k) + " overlaps another (a node no parent reaches?)");
        used[at + q] = true;
      }
      out.words[at] = enc.words[w];
      for (uint32_t q = 1; q < size; ++q) {  // the child at old word p moves to its node's new word
        const uint32_t p = enc.words[w + q];
        if (p >= moved.size() || moved[p] == kNone || moved[p] < base) throw fail("a pointer to word " + std::to_string(p));
        if (moved[p] - base > UINT32_MAX)
          throw Error("paged stream: level " + std::to_string(l - 1) + " holds more than 2^32 words");
        out.words[at + q] = static_cast<uint32_t>(moved[p] - base);
      }
      w += size;
    }
  }
  if (k != lay.old_at.size() || lay.at[0] != 0) throw fail("the node count or the root's place differs");
  return out;
}

EncodedDag level_order_stream(const EncodedDag& paged, uint32_t page_words) {
  auto fail = [](const std::string& why) { return Error("paged stream: " + why); };
  if (paged.encoding == Encoding::ssvdag) throw fail("svo, svdag and ussvdag only (an ssvdag: paged_ssvdag.h)");
  if (page_words < kMaxNodeWords) throw fail("pages of " + std::to_string(page_words) + " words cannot hold a node");
  const std::vector<uint32_t>& in = paged.words;
  const uint64_t n = in.size();
  const uint32_t L = paged.levels;
  EncodedDag out;
  out.encoding = paged.encoding;
  out.levels = L;
  if (L > 21) throw fail("bad level count " + std::to_string(L));
  out.level_offset.assign(L + 1, 0);
  if (n == 0) return out;
  if (L == 0) throw fail("nodes without levels");
  if (n >= UINT32_MAX - 1) throw fail(std::to_string(n) + " words: more than this check holds (2^32 - 2)");
  // Level order: the levels' starts, root first, each level a non-empty run of the stream. Subtree order: none.
  const std::vector<uint64_t>& starts = paged.level_offset;
  const bool relative = !starts.empty();
  auto ends_at = [&](uint32_t l) { return l == 1 ? n : starts[l - 1]; };
  if (relative) {
    bool ok = starts.size() == L + 1u && starts[L] == 0;
    for (uint32_t l = L; ok && l >= 1; --l) ok = starts[l] < ends_at(l);
    if (!ok) throw fail("bad level starts");
  }

  // placed[w]: for a node's first word, its word in the output; for its other words kInside; else kFree.
  // Every input word is claimed at most once, so the output is never longer than the input.
  constexpr uint32_t kFree = UINT32_MAX, kInside = UINT32_MAX - 1;
  std::vector<uint32_t> placed(n, kFree);
  uint64_t next_at = 0;  // output word of the next node discovered
  std::vector<uint32_t> level, below;  // input words of this level's and the next level's nodes, in output order
  auto claim = [&](uint64_t w, uint32_t l, uint64_t from) {
    const uint32_t header = in[w];
    const uint32_t mask = header & 0xffu;
    const uint32_t mirrors = paged.encoding == Encoding::ussvdag && l > 1 ? header >> 8 : 0;
    if (mask == 0 || header >> 8 != mirrors || (mirrors & ~(mask * 0x10101u)) != 0)
      throw fail("word " + std::to_string(w) + " (reached from word " + std::to_string(from) +
                 ") is not a node header of level " + std::to_string(l));
    const uint32_t size = node_words(header, l);
    if (w + uint64_t{size} > (relative ? ends_at(l) : n))
      throw fail("the node at word " + std::to_string(w) + " runs past the end of " +
                 (relative ? "level " + std::to_string(l) : std::string("the stream")));
    if (w / page_words != (w + size - 1) / page_words)
      throw fail("the node at word " + std::to_string(w) + " crosses a page boundary");
    for (uint32_t q = 0; q < size; ++q)
      if (placed[w + q] != kFree) throw fail("the node at word " + std::to_string(w) + " overlaps another node");
    placed[w] = static_cast<uint32_t>(next_at);
    for (uint32_t q = 1; q < size; ++q) placed[w + q] = kInside;
    next_at += size;
    below.push_back(static_cast<uint32_t>(w));
  };
  claim(0, L, 0);
  level.swap(below);
  out.words.reserve(next_at);
  for (uint32_t l = L; l >= 1; --l) {
    out.level_offset[l] = out.words.size();
    const uint64_t level_end = next_at;  // this level's nodes are all known: the next level starts here
    below.clear();
    for (uint32_t w : level) {
      const uint32_t header = in[w];
      out.words.push_back(header);
      if (l == 1) continue;
      const size_t first = out.words.size();
      out.words.resize(first + node_words(header, l) - 1);
      for (uint32_t c = 0; c < 8; ++c) {  // children by ascending Morton octant: their discovery order
        if (!(header >> mv_xmajor_octant(c) & 1)) continue;
        const uint32_t q = w + pointer_of(header, c);
        const uint64_t child = relative ? starts[l - 1] + in[q] : in[q];
        if (child >= (relative ? ends_at(l - 1) : n))
          throw fail("word " + std::to_string(q) + " points to " + std::to_string(child) + ", past the end of " +
                     (relative ? "level " + std::to_string(l - 1) : std::string("the stream")));
        if (placed[child] == kFree) {
          claim(child, l - 1, q);
        } else if (placed[child] == kInside || placed[child] < level_end) {
          throw fail("word " + std::to_string(q) + " points to " + std::to_string(child) +
                     ", not the start of a node of level " + std::to_string(l - 1));
        }
        out.words[first - 1 + pointer_of(header, c)] = placed[child];
      }
    }
    level.swap(below);
  }
  for (uint64_t w = 0; w < n; ++w)
    if (placed[w] == kFree && in[w] != 0)
      throw fail("word " + std::to_string(w) + " is neither in a node reached from the root nor zero padding");
  return out;
}

}  // namespace mv

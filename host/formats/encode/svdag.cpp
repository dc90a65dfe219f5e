// The svdag encoding (layout in include/megavox/encode.h).
#include <algorithm>
#include <string>

#include "common/trace_nodes.h"
#include "megavox/encode.h"
#include "megavox/error.h"
#include "node_starts.h"

namespace mv {

EncodedDag encode_svdag(const Dag& dag) {
  EncodedDag enc;
  enc.encoding = dag.symmetric ? Encoding::ussvdag : dag.reduced ? Encoding::svdag : Encoding::svo;
  enc.levels = dag.levels;
  enc.level_offset.assign(dag.levels + 1, 0);
  if (dag.levels == 0 || dag.voxels == 0) return enc;
  // Word position of every node: levels root first, a node takes 1 + popcount words (leaves: 1).
  std::vector<std::vector<uint64_t>> at(dag.levels + 1);
  uint64_t words = 0;
  for (uint32_t l = dag.levels; l >= 1; --l) {
    enc.level_offset[l] = words;
    const auto& masks = dag.level[l].mask;
    at[l].resize(masks.size());
    for (size_t i = 0; i < masks.size(); ++i) {
      at[l][i] = words;
      words += l == 1 ? 1 : 1 + __builtin_popcount(masks[i]);
    }
  }
  if (words > UINT32_MAX) throw Error("svdag: " + std::to_string(words) + " words exceed 32-bit pointers");
  enc.words.reserve(words);
  for (uint32_t l = dag.levels; l >= 1; --l) {
    const DagLevel& lv = dag.level[l];
    for (size_t i = 0; i < lv.mask.size(); ++i) {
      uint32_t tm = mv_xmajor_mask(lv.mask[i]);
      if (l == 1) {
        enc.words.push_back(tm);
        continue;
      }
      uint32_t child_at[8] = {};  // by x-major octant
      uint32_t header = tm;
      for (uint32_t c = 0, k = 0; c < 8; ++c) {
        if (!(lv.mask[i] >> c & 1)) continue;
        uint32_t j = lv.first[i] + k++;
        uint32_t t = mv_xmajor_octant(c);
        child_at[t] = static_cast<uint32_t>(at[l - 1][lv.children[j]]);
        uint32_t tag = lv.tags.empty() ? 0 : lv.tags[j];
        header |= (tag & 1) << (8 + t) | (tag >> 1 & 1) << (16 + t) | (tag >> 2 & 1) << (24 + t);
      }
      enc.words.push_back(header);
      for (int t = 7; t >= 0; --t)
        if (tm >> t & 1) enc.words.push_back(child_at[t]);
    }
  }
  return enc;
}

void validate_svdag(const EncodedDag& enc) {
  if (enc.words.empty()) return;
  const uint32_t L = enc.levels;
  auto fail = [](const std::string& why) { return Error("svdag: " + why); };
  if (L == 0 || L > 21 || enc.level_offset.size() != L + 1) throw fail("bad level count");
  if (enc.level_offset[L] != 0) throw fail("the root level must start at word 0");
  // One linear walk per level, bottom-up: node sizes must tile the level, and every pointer must land on a
  // node start one level down (so the graph is acyclic and complete without following any path).
  NodeStarts starts(enc.words.size());
  uint64_t below_begin = 0, below_end = 0, here_nodes = 0;
  for (uint32_t l = 1; l <= L; ++l) {
    uint64_t begin = enc.level_offset[l];
    uint64_t end = l == 1 ? enc.words.size() : enc.level_offset[l - 1];
    if (begin > end || end > enc.words.size()) throw fail("level " + std::to_string(l) + " lies outside the stream");
    here_nodes = 0;
    for (uint64_t w = begin; w < end;) {
      starts.set(w);
      ++here_nodes;
      uint32_t header = enc.words[w];
      uint32_t mask = header & 0xff;
      uint32_t mirrors = enc.encoding == Encoding::ussvdag && l > 1 ? header >> 8 : 0;
      bool stray = (mirrors & ~(mask * 0x10101u)) != 0;  // mirror bits only for children that exist
      if (mask == 0 || (header >> 8) != mirrors || stray)
        throw fail("word " + std::to_string(w) + " is not a node header");
      uint64_t next = w + (l == 1 ? 1 : 1 + __builtin_popcount(mask));
      if (next > end) throw fail("node at word " + std::to_string(w) + " runs past its level");
      for (uint64_t q = w + 1; q < next; ++q) {
        const uint32_t p = enc.words[q];
        if (p < below_begin || p >= below_end || !starts.test(p))
          throw fail("word " + std::to_string(q) + " points to " + std::to_string(enc.words[q]) +
                     ", not a node of level " + std::to_string(l - 1));
      }
      w = next;
    }
    below_begin = begin, below_end = end;
  }
  if (here_nodes != 1) throw fail("the root level must hold exactly one node");
}

std::vector<uint64_t> encoded_octree_nodes_svdag(const EncodedDag& enc) {
  if (enc.words.empty()) return {};
  const uint32_t L = enc.levels;
  auto add = [](uint64_t a, uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; };
  std::vector<uint64_t> paths(enc.words.size(), 0), out(L + 1, 0);
  paths[0] = 1;
  // Levels are stored root first, so every node's paths are complete before its level is walked.
  for (uint32_t l = L; l >= 1; --l) {
    const uint64_t end = l == 1 ? enc.words.size() : enc.level_offset[l - 1];
    for (uint64_t w = enc.level_offset[l]; w < end;) {
      const uint32_t mask = enc.words[w] & 0xff, kids = __builtin_popcount(mask);
      out[l] = add(out[l], paths[w]);
      if (l == 1) {
        const uint64_t v = paths[w] > UINT64_MAX / 8 ? UINT64_MAX : paths[w] * kids;
        out[0] = add(out[0], v);
        w += 1;
        continue;
      }
      for (uint64_t q = w + 1; q <= w + kids; ++q) paths[enc.words[q]] = add(paths[enc.words[q]], paths[w]);
      w += 1 + kids;
    }
  }
  return out;
}

std::vector<uint64_t> encoded_subtree_sizes_svdag(const EncodedDag& enc) {
  std::vector<uint64_t> size(enc.words.size(), 0);
  auto add = [](uint64_t a, uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; };
  // Levels bottom-up, so a node's children are sized before it.
  for (uint32_t l = 1; l <= enc.levels && !enc.words.empty(); ++l) {
    const uint64_t end = l == 1 ? enc.words.size() : enc.level_offset[l - 1];
    for (uint64_t w = enc.level_offset[l]; w < end;) {
      const uint32_t mask = enc.words[w] & 0xff, kids = __builtin_popcount(mask);
      if (l == 1) {
        size[w++] = 1 + kids;
        continue;
      }
      uint64_t s = 1;
      for (uint64_t q = w + 1; q <= w + kids; ++q) s = add(s, size[enc.words[q]]);
      size[w] = s;
      w += 1 + kids;
    }
  }
  return size;
}

std::vector<uint64_t> decode_svdag(const EncodedDag& enc) {
  validate_svdag(enc);
  std::vector<uint64_t> out;
  if (enc.words.empty()) return out;
  struct Item {
    uint32_t level, word, reflect;  // the subtree is the stored node mirrored by `reflect`
    uint64_t prefix;
  };
  std::vector<Item> stack{{enc.levels, 0, 0, 0}};
  while (!stack.empty()) {
    Item it = stack.back();
    stack.pop_back();
    uint32_t header = enc.words[it.word];
    uint32_t ptr = it.word + 1;
    for (int t = 7; t >= 0; --t) {
      if (!(header >> t & 1)) continue;
      uint64_t key = it.prefix << 3 | (mv_xmajor_octant(uint32_t(t)) ^ it.reflect);
      if (it.level == 1) {
        out.push_back(key);
        continue;
      }
      uint32_t tag = (header >> (8 + t) & 1) | (header >> (16 + t) & 1) << 1 | (header >> (24 + t) & 1) << 2;
      stack.push_back({it.level - 1, enc.words[ptr++], it.reflect ^ tag, key});
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace mv

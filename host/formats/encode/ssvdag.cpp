// The compact ssvdag encoding (layout in include/megavox/encode.h).
#include <algorithm>
#include <string>

#include "common/ssvdag.h"
#include "common/trace_nodes.h"
#include "encode/node_order.h"
#include "megavox/encode.h"
#include "megavox/error.h"

namespace mv {

namespace {

// Bit of voxel (x, y, z), each 0..3, in a 4x4x4 brick.
constexpr uint32_t brick_bit(uint32_t x, uint32_t y, uint32_t z) { return 16 * x + 4 * y + z; }

// The 64-bit brick of level-2 node i: its 2x2x2 children, each mirrored by its tag, at their octants.
uint64_t make_brick(const Dag& dag, uint32_t i) {
  const DagLevel& lv = dag.level[2];
  uint64_t brick = 0;
  for (uint32_t c = 0, k = 0; c < 8; ++c) {
    if (!(lv.mask[i] >> c & 1)) continue;
    uint32_t j = lv.first[i] + k++;
    uint32_t m = mv_reflect_mask(dag.level[1].mask[lv.children[j]], lv.tags.empty() ? 0 : lv.tags[j]);
    for (uint32_t v = 0; v < 8; ++v)
      if (m >> v & 1)
        brick |= uint64_t{1} << brick_bit(2 * (c & 1) + (v & 1), 2 * (c >> 1 & 1) + (v >> 1 & 1),
                                          2 * (c >> 2 & 1) + (v >> 2 & 1));
  }
  return brick;
}

// Tag bits (x, y, z) to the pointer's mirror bits 13 (X), 14 (Y), 15 (Z) of its first 16-bit word.
constexpr uint32_t mirror_bits(uint32_t tag) { return (tag & 7) << 13; }

}  // namespace

EncodedDag encode_ssvdag(const Dag& dag) {
  const uint32_t L = dag.levels;
  if (L < 3) throw Error("ssvdag encoding needs at least 3 levels (an 8^3 grid)");
  EncodedDag enc;
  enc.encoding = Encoding::ssvdag;
  enc.levels = L;
  enc.level_offset.assign(L + 1, 0);
  if (dag.voxels == 0) return enc;

  // Order of each level (2 .. L): by descending reference count, ties by first-met order (node_order.h: a
  // function of the DAG's shape alone, which the paged ssvdag's way back computes again).
  auto count = [&](uint32_t l) { return static_cast<uint32_t>(dag.level[l].mask.size()); };
  auto children = [&](uint32_t l, uint32_t i, auto&& f) {
    const DagLevel& lv = dag.level[l];
    for (uint32_t c = 0, k = 0; c < 8; ++c)
      if (lv.mask[i] >> c & 1) f(c, lv.children[lv.first[i] + k++]);
  };
  const std::vector<std::vector<uint32_t>> order = resident_node_order(L, count, children);
  std::vector<std::vector<uint32_t>> position(L + 1);
  for (uint32_t l = 2; l <= L; ++l) {
    position[l].resize(order[l].size());
    for (uint32_t p = 0; p < order[l].size(); ++p) position[l][order[l][p]] = p;
  }
  for (uint32_t i : order[2]) enc.bricks.push_back(make_brick(dag, i));
  if (enc.bricks.size() > (uint64_t{1} << 30)) throw Error("ssvdag: more than 2^30 bricks");

  // Inner levels bottom-up: a node's size depends on its children's offsets.
  std::vector<std::vector<uint16_t>> streams(L + 1);
  std::vector<std::vector<uint64_t>> offset(L + 1);  // level l: offset of node (by id) in its stream
  offset[2].resize(dag.level[2].mask.size());
  for (uint32_t i = 0; i < offset[2].size(); ++i) offset[2][i] = position[2][i];
  for (uint32_t l = 3; l <= L; ++l) {
    const DagLevel& lv = dag.level[l];
    offset[l].resize(lv.mask.size());
    std::vector<uint16_t>& out = streams[l];
    for (uint32_t i : order[l]) {
      offset[l][i] = out.size();
      uint32_t child_off[8] = {}, child_tag[8] = {}, header = 0;
      for (uint32_t c = 0, k = 0; c < 8; ++c) {
        if (!(lv.mask[i] >> c & 1)) continue;
        uint32_t j = lv.first[i] + k++;
        uint32_t t = mv_xmajor_octant(c);
        uint64_t off = offset[l - 1][lv.children[j]];
        if (off >= (uint64_t{1} << 30)) throw Error("ssvdag: an offset needs more than 30 bits");
        child_off[t] = static_cast<uint32_t>(off);
        child_tag[t] = lv.tags.empty() ? 0 : lv.tags[j];
        uint32_t code = off < (1u << 13) ? 1 : 2 + static_cast<uint32_t>(off >> 29 & 1);
        header |= code << (2 * t);
      }
      out.push_back(static_cast<uint16_t>(header));
      for (int t = 7; t >= 0; --t) {
        uint32_t code = header >> (2 * t) & 3;
        if (code == 1) {
          out.push_back(static_cast<uint16_t>(mirror_bits(child_tag[t]) | child_off[t]));
        } else if (code >= 2) {
          uint32_t word = mirror_bits(child_tag[t]) << 16 | (child_off[t] & 0x1fffffffu);
          out.push_back(static_cast<uint16_t>(word >> 16));
          out.push_back(static_cast<uint16_t>(word & 0xffff));
        }
      }
    }
  }
  for (uint32_t l = L; l >= 3; --l) {
    enc.level_offset[l] = enc.inner.size();
    enc.inner.insert(enc.inner.end(), streams[l].begin(), streams[l].end());
  }
  return enc;
}

namespace {

// A child pointer read from a node: its level-relative offset and mirror tag.
struct Pointer {
  uint64_t offset;
  uint32_t tag;
};

// Reads node header `h` at inner word w: calls f(x-major octant, pointer) for each child; returns the words
// after the node. No checks (validate_ssvdag does those).
template <class F>
uint64_t read_node(const std::vector<uint16_t>& in, uint64_t w, F&& f) {
  uint32_t header = in[w++];
  for (int t = 7; t >= 0; --t) {
    uint32_t code = header >> (2 * t) & 3;
    if (code == 0) continue;
    uint32_t first = in[w++];
    if (code == 1) {
      f(uint32_t(t), Pointer{first & 0x1fffu, first >> 13});
    } else {
      uint32_t word = first << 16 | in[w++];
      f(uint32_t(t), Pointer{(word & 0x1fffffffu) | uint64_t(code & 1) << 29, word >> 29});
    }
  }
  return w;
}

uint64_t node_words(uint32_t header) {
  uint64_t n = 1;
  for (uint32_t t = 0; t < 8; ++t) n += std::min<uint32_t>(header >> (2 * t) & 3, 2);
  return n;
}

}  // namespace

void validate_ssvdag(const EncodedDag& enc) {
  auto fail = [](const std::string& why) { return Error("ssvdag: " + why); };
  const uint32_t L = enc.levels;
  if (enc.inner.empty() && enc.bricks.empty()) return;
  if (L < 3 || L > 21 || enc.level_offset.size() != L + 1) throw fail("bad level count");
  if (enc.level_offset[L] != 0) throw fail("the root level must start at word 0");
  // Bottom-up, one linear walk per inner level: sizes tile the level; pointers land on node starts of the
  // level below (or on bricks), so the graph is acyclic without following any path.
  std::vector<uint64_t> below, here;
  for (uint32_t l = 3; l <= L; ++l) {
    uint64_t begin = enc.level_offset[l];
    uint64_t end = l == 3 ? enc.inner.size() : enc.level_offset[l - 1];
    if (begin > end || end > enc.inner.size()) throw fail("level " + std::to_string(l) + " lies outside the stream");
    here.clear();
    for (uint64_t w = begin; w < end;) {
      uint32_t header = enc.inner[w];
      if (header == 0) throw fail("word " + std::to_string(w) + " is an empty node");
      if (w + node_words(header) > end) throw fail("node at word " + std::to_string(w) + " runs past its level");
      here.push_back(w - begin);
      bool ok = true;
      read_node(enc.inner, w, [&](uint32_t, Pointer p) {
        ok = ok && (l == 3 ? p.offset < enc.bricks.size() : std::binary_search(below.begin(), below.end(), p.offset));
      });
      if (!ok) throw fail("node at word " + std::to_string(w) + " points outside level " + std::to_string(l - 1));
      w += node_words(header);
    }
    below.swap(here);
  }
  if (below.size() != 1) throw fail("the root level must hold exactly one node");
}

std::vector<uint64_t> decode_ssvdag(const EncodedDag& enc) {
  validate_ssvdag(enc);
  std::vector<uint64_t> out;
  if (enc.inner.empty()) return out;
  struct Item {
    uint32_t level;
    uint64_t offset;
    uint32_t reflect;
    uint64_t prefix;
  };
  std::vector<Item> stack{{enc.levels, 0, 0, 0}};
  while (!stack.empty()) {
    Item it = stack.back();
    stack.pop_back();
    read_node(enc.inner, enc.level_offset[it.level] + it.offset, [&](uint32_t t, Pointer p) {
      uint64_t key = it.prefix << 3 | (mv_xmajor_octant(t) ^ it.reflect);
      uint32_t reflect = it.reflect ^ p.tag;
      if (it.level > 3) {
        stack.push_back({it.level - 1, p.offset, reflect, key});
        return;
      }
      uint64_t brick = enc.bricks[p.offset];
      for (uint32_t x = 0; x < 4; ++x)
        for (uint32_t y = 0; y < 4; ++y)
          for (uint32_t z = 0; z < 4; ++z) {
            if (!(brick >> brick_bit(x, y, z) & 1)) continue;
            // the brick's voxel (x, y, z), mirrored by `reflect` within the brick
            uint32_t rx = reflect & 1 ? 3 - x : x, ry = reflect & 2 ? 3 - y : y, rz = reflect & 4 ? 3 - z : z;
            uint32_t c = (rx >> 1) | (ry >> 1) << 1 | (rz >> 1) << 2, v = (rx & 1) | (ry & 1) << 1 | (rz & 1) << 2;
            out.push_back((key << 3 | c) << 3 | v);
          }
    });
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<uint64_t> encoded_octree_nodes(const EncodedDag& enc) {
  if (enc.encoding != Encoding::ssvdag) return encoded_octree_nodes_svdag(enc);
  if (enc.inner.empty()) return {};
  const uint32_t L = enc.levels;
  auto add = [](uint64_t a, uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; };
  auto times = [](uint64_t a, uint64_t k) { return k && a > UINT64_MAX / k ? UINT64_MAX : a * k; };
  std::vector<uint64_t> out(L + 1, 0), here(1, 1), below;
  // Levels root first; a pointer's offset is relative to its child level (bricks at level 2).
  for (uint32_t l = L; l >= 3; --l) {
    const uint64_t begin = enc.level_offset[l], end = l == 3 ? enc.inner.size() : enc.level_offset[l - 1];
    const uint64_t child_words =
        l == 3 ? enc.bricks.size() : (l - 1 == 3 ? enc.inner.size() : enc.level_offset[l - 2]) - enc.level_offset[l - 1];
    below.assign(child_words, 0);
    for (uint64_t w = begin; w < end;) {
      const uint64_t n = here[w - begin];
      out[l] = add(out[l], n);
      w = read_node(enc.inner, w, [&](uint32_t, Pointer p) { below[p.offset] = add(below[p.offset], n); });
    }
    here.swap(below);
  }
  for (size_t b = 0; b < enc.bricks.size(); ++b) {
    const uint64_t n = here[b], brick = enc.bricks[b];
    out[2] = add(out[2], n);
    uint32_t cells = 0;
    for (uint32_t c = 0; c < 8; ++c) {  // the 2x2x2 cells of the brick that hold a voxel
      uint64_t cell = 0;
      for (uint32_t v = 0; v < 8; ++v)
        cell |= brick >> brick_bit(2 * (c & 1) + (v & 1), 2 * (c >> 1 & 1) + (v >> 1 & 1), 2 * (c >> 2) + (v >> 2)) & 1;
      cells += static_cast<uint32_t>(cell);
    }
    out[1] = add(out[1], times(n, cells));
    out[0] = add(out[0], times(n, static_cast<uint64_t>(__builtin_popcountll(brick))));
  }
  return out;
}

std::vector<uint64_t> encoded_subtree_sizes_svdag(const EncodedDag& enc);  // svdag.cpp

std::vector<uint64_t> encoded_subtree_sizes(const EncodedDag& enc) {
  if (enc.encoding != Encoding::ssvdag) return encoded_subtree_sizes_svdag(enc);
  std::vector<uint64_t> size(enc.inner.size(), 0);
  auto add = [](uint64_t a, uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; };
  auto brick_size = [](uint64_t brick) {
    uint64_t s = 1 + static_cast<uint64_t>(__builtin_popcountll(brick));
    for (uint32_t x = 0; x < 2; ++x)  // the full 2x2x2 sub-blocks
      for (uint32_t y = 0; y < 2; ++y)
        for (uint32_t z = 0; z < 2; ++z) {
          uint64_t cell = 0;
          for (uint32_t v = 0; v < 8; ++v)
            cell |= brick >> brick_bit(2 * x + (v & 1), 2 * y + (v >> 1 & 1), 2 * z + (v >> 2)) & 1;
          s += cell;
        }
    return s;
  };
  // Levels bottom-up (level 3 last in the stream); pointers are relative to the child level's start.
  for (uint32_t l = 3; l <= enc.levels && !enc.inner.empty(); ++l) {
    const uint64_t begin = enc.level_offset[l], end = l == 3 ? enc.inner.size() : enc.level_offset[l - 1];
    for (uint64_t w = begin; w < end;) {
      uint64_t s = 1;
      const uint64_t next = read_node(enc.inner, w, [&](uint32_t, Pointer p) {
        s = add(s, l == 3 ? brick_size(enc.bricks[p.offset]) : size[enc.level_offset[l - 1] + p.offset]);
      });
      size[w] = s;
      w = next;
    }
  }
  return size;
}

void validate_encoded(const EncodedDag& enc) {
  if (enc.encoding == Encoding::ssvdag) validate_ssvdag(enc);
  else validate_svdag(enc);
}

std::vector<uint64_t> decode_encoded(const EncodedDag& enc) {
  return enc.encoding == Encoding::ssvdag ? decode_ssvdag(enc) : decode_svdag(enc);
}

}  // namespace mv

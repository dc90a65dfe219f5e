#include "trace/trace_layout.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "common/trace_colour.h"
#include "megavox/error.h"

namespace mv {

std::vector<uint32_t> trace_words(const EncodedDag& dag) {
  if (dag.encoding != Encoding::ssvdag) return dag.words;
  std::vector<uint32_t> words(std::max<size_t>((dag.inner.size() + 1) / 2, 1) + 1, 0);  // an empty one too
  if (!dag.inner.empty()) std::memcpy(words.data(), dag.inner.data(), dag.inner.size() * 2);
  return words;
}

std::vector<uint32_t> trace_bricks(const EncodedDag& dag) {
  std::vector<uint32_t> halves(dag.bricks.size() * 2);
  if (!dag.bricks.empty()) std::memcpy(halves.data(), dag.bricks.data(), dag.bricks.size() * 8);
  return halves;
}

std::vector<uint32_t> trace_level_offsets(const EncodedDag& dag) {
  if (dag.encoding != Encoding::ssvdag) return {};
  std::vector<uint32_t> offsets(dag.levels + 1, 0);
  for (uint32_t l = 0; l <= dag.levels && l < dag.level_offset.size(); ++l)
    offsets[l] = static_cast<uint32_t>(dag.level_offset[l]);
  return offsets;
}

std::vector<uint32_t> trace_colour_meta(const EncodedDag& dag) {
  const std::vector<uint64_t> sizes = encoded_subtree_sizes(dag);
  const uint32_t at = MV_COLOUR_SIZES_AT(dag.levels);
  std::vector<uint32_t> meta(at + sizes.size(), 0);
  const std::vector<uint32_t> starts = trace_level_offsets(dag);
  std::copy(starts.begin(), starts.end(), meta.begin());
  if (!sizes.empty() && sizes[0] > UINT32_MAX)
    throw Error("trace: the DAG has " + std::to_string(sizes[0]) +
                " octree nodes; a hit's colour index is 32-bit (at most 2^32 - 1 nodes)");
  for (size_t i = 0; i < sizes.size(); ++i) meta[at + i] = static_cast<uint32_t>(sizes[i]);
  return meta;
}

std::vector<uint32_t> trace_colour_words(const std::vector<uint8_t>& rgb, const ColourPalette* palette) {
  auto packed = [](const uint8_t* c) { return c[0] | uint32_t{c[1]} << 8 | uint32_t{c[2]} << 16; };
  std::vector<uint32_t> words(MV_COLOUR_HEAD, 0);
  if (!palette) {
    words[0] = MV_COLOUR_RAW;
    for (size_t i = 0; i + 2 < rgb.size(); i += 3) words.push_back(packed(&rgb[i]));
    return words;
  }
  const ColourPalette& p = *palette;
  if (p.index_bits() >= (uint64_t{1} << 32) || p.palette_entries() * p.material_bits >= (uint64_t{1} << 32))
    throw Error("trace: the colour palette's bits pass 32-bit offsets");
  words[0] = MV_COLOUR_PALETTE;
  words[1] = static_cast<uint32_t>(p.blocks());
  words[2] = p.material_bits;
  auto start = [&](uint32_t slot) { words[slot] = static_cast<uint32_t>(words.size()); };
  start(MV_COLOUR_AT_DIRECTORY);
  words.insert(words.end(), p.block_start.begin(), p.block_start.end());
  start(MV_COLOUR_AT_BLOCKS);
  for (size_t g = 0; g < p.blocks(); ++g)
    words.insert(words.end(), {p.block_palette[g], static_cast<uint32_t>(p.block_bit[g]),
                               uint32_t{p.palette_omega[p.block_palette[g]]}});
  start(MV_COLOUR_AT_PALETTES);
  for (uint64_t b : p.palette_bit) words.push_back(static_cast<uint32_t>(b));
  start(MV_COLOUR_AT_MATERIALS);
  for (size_t m = 0; m < p.materials_count(); ++m) words.push_back(packed(&p.materials[3 * m]));
  auto halves = [&](const std::vector<uint64_t>& w) {  // LSB first, then the spare word a two-word read may touch
    for (uint64_t x : w) words.insert(words.end(), {static_cast<uint32_t>(x), static_cast<uint32_t>(x >> 32)});
    words.push_back(0);
  };
  start(MV_COLOUR_AT_PALETTE_WORDS);
  halves(p.palette_words);
  start(MV_COLOUR_AT_INDEX_WORDS);
  halves(p.index_words);
  return words;
}

void set_trace_levels(MvTraceParams& p, const EncodedDag& dag) {
  p.mode = MV_TRACE_MODE(dag.levels, 0u, 0u, 0u);
  if (dag.encoding != Encoding::ssvdag) return;
  for (uint32_t k = 0; k < MV_TRACE_PARAM_LEVELS && 3 + k < dag.level_offset.size(); ++k)
    p.level_base[k] = static_cast<uint32_t>(dag.level_offset[3 + k]);
}

}  // namespace mv

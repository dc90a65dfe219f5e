// Palette compression of the attribute array (megavox/colour_palette.h): Algorithm 1 of Kol's thesis, its stored
// form and its checked parse.
#include "megavox/colour_palette.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstring>
#include <map>
#include <string>

#include "megavox/error.h"

namespace mv {
namespace {

// MEMORY()'s directory term: one directory entry as stored (start and palette, 2 x uint32).
constexpr uint64_t kPaletteDirBits = 64;
// Phase 1 tries blocks of up to 2^3 distinct indices (the thesis stops there: "16 unique indices or more" is
// too costly to search), phase 2 up to 2^8.
constexpr uint32_t kPalettePhase1Omegas = 4, kPalettePhase2Omegas = 9;
constexpr uint32_t kPaletteChunk = 32;  // entries per leaf of the largest-window search tree

uint32_t palette_ceil_log2(uint64_t n) {
  uint32_t b = 0;
  while ((uint64_t{1} << b) < n) ++b;
  return b;
}

void palette_put_bits(std::vector<uint64_t>& w, uint64_t at, uint64_t v, uint32_t width) {
  if (width == 0) return;
  const uint64_t word = at >> 6;
  const uint32_t off = at & 63;
  w[word] |= v << off;
  if (off + width > 64) w[word + 1] |= v >> (64 - off);
}

uint64_t palette_get_bits(const std::vector<uint64_t>& w, uint64_t at, uint32_t width) {
  if (width == 0) return 0;
  const uint64_t word = at >> 6;
  const uint32_t off = at & 63;
  uint64_t v = w[word] >> off;
  if (off + width > 64) v |= w[word + 1] << (64 - off);
  return v & ((uint64_t{1} << width) - 1);
}

uint64_t palette_words_for(uint64_t bits) { return (bits + 63) / 64; }
uint64_t palette_pad8(uint64_t bytes) { return (bytes + 7) / 8 * 8; }

// ends[k]: the end (exclusive) of the longest run of entries from k holding at most `cap` distinct indices.
// Nondecreasing in k (two pointers).
std::vector<uint32_t> palette_window_ends(const std::vector<uint32_t>& m, uint32_t lambda, uint32_t cap) {
  const size_t n = m.size();
  std::vector<uint32_t> count(lambda, 0), ends(n);
  uint32_t distinct = 0;
  size_t r = 0;
  for (size_t k = 0; k < n; ++k) {
    while (r < n && (count[m[r]] > 0 || distinct < cap)) {
      if (count[m[r]]++ == 0) ++distinct;
      ++r;
    }
    ends[k] = static_cast<uint32_t>(r);
    if (--count[m[k]] == 0) --distinct;
  }
  return ends;
}

// The largest block inside [i, j) with at most `cap` distinct indices, leftmost on ties: windows ending inside
// [i, j) are a prefix of the starts (ends are nondecreasing), searched by a max tree over chunks of starts; the
// first start whose window passes j gives the only clipped candidate worth having.
class PaletteLargestWindow {
 public:
  explicit PaletteLargestWindow(std::vector<uint32_t> ends) : ends_(std::move(ends)) {
    const size_t chunks = (ends_.size() + kPaletteChunk - 1) / kPaletteChunk;
    leaves_ = 1;
    while (leaves_ < chunks) leaves_ *= 2;
    tree_.assign(2 * leaves_, 0);
    for (size_t k = 0; k < ends_.size(); ++k) tree_[leaves_ + k / kPaletteChunk] = std::max(tree_[leaves_ + k / kPaletteChunk], key(k));
    for (size_t t = leaves_ - 1; t >= 1; --t) tree_[t] = std::max(tree_[2 * t], tree_[2 * t + 1]);
  }
  const std::vector<uint32_t>& ends() const { return ends_; }

  std::pair<uint32_t, uint32_t> largest(uint32_t i, uint32_t j) const {
    const uint32_t p = static_cast<uint32_t>(std::upper_bound(ends_.begin() + i, ends_.begin() + j, j) - ends_.begin());
    uint32_t start = p, length = j - p;
    if (p > i) {
      const uint64_t best = range_max(i, p);
      const uint32_t len = static_cast<uint32_t>(best >> 32);
      if (len >= length) start = 0xffffffffu - static_cast<uint32_t>(best), length = len;
    }
    return {start, start + length};
  }

 private:
  // Larger length first, then the smaller start.
  uint64_t key(size_t k) const { return uint64_t{ends_[k] - uint32_t(k)} << 32 | (0xffffffffu - uint32_t(k)); }
  uint64_t range_max(size_t a, size_t b) const {
    uint64_t best = 0;
    const size_t ca = a / kPaletteChunk, cb = b / kPaletteChunk;
    if (ca == cb) {
      for (size_t k = a; k < b; ++k) best = std::max(best, key(k));
      return best;
    }
    for (size_t k = a; k < (ca + 1) * kPaletteChunk; ++k) best = std::max(best, key(k));
    for (size_t k = cb * kPaletteChunk; k < b; ++k) best = std::max(best, key(k));
    for (size_t l = leaves_ + ca + 1, r = leaves_ + cb; l < r; l /= 2, r /= 2) {
      if (l & 1) best = std::max(best, tree_[l++]);
      if (r & 1) best = std::max(best, tree_[--r]);
    }
    return best;
  }

  std::vector<uint32_t> ends_;
  std::vector<uint64_t> tree_;
  size_t leaves_ = 1;
};

struct PaletteSelection {
  const std::vector<uint32_t>& m;
  uint32_t b;  // ceil(log2 λ)
  std::vector<PaletteLargestWindow> large;           // ω = 0 .. 3
  std::vector<std::vector<uint32_t>> ends;    // ω = 4 .. 8 (0 .. 3 live in `large`)
  std::vector<std::pair<uint32_t, uint32_t>> blocks;

  const std::vector<uint32_t>& ends_of(uint32_t omega) const {
    return omega < kPalettePhase1Omegas ? large[omega].ends() : ends[omega - kPalettePhase1Omegas];
  }

  // FINDREMAININGBLOCKS: from the left, the block (of nine) with the least memory per entry.
  void remaining(uint32_t i, uint32_t j) {
    while (i < j) {
      uint64_t best_cost = 0, best_len = 0;
      for (uint32_t omega = 0; omega < kPalettePhase2Omegas; ++omega) {
        const uint64_t len = std::min(ends_of(omega)[i], j) - i;
        const uint64_t cost = len * omega + (uint64_t{1} << omega) * b + kPaletteDirBits;
        if (best_len == 0 || static_cast<unsigned __int128>(cost) * best_len < static_cast<unsigned __int128>(best_cost) * len)
          best_cost = cost, best_len = len;
      }
      blocks.push_back({i, i + static_cast<uint32_t>(best_len)});
      i += static_cast<uint32_t>(best_len);
    }
  }

  // FINDLARGEBLOCKS: take the largest block of 2^ω distinct indices while its palette and directory entry cost
  // less than one bit per entry, recurse on both sides; else FINDREMAININGBLOCKS. An explicit stack: the
  // result does not depend on the order the ranges are taken.
  void large_blocks(uint32_t n) {
    std::vector<std::pair<uint32_t, uint32_t>> ranges = {{0, n}};
    while (!ranges.empty()) {
      const auto [i, j] = ranges.back();
      ranges.pop_back();
      if (i >= j) continue;
      bool taken = false;
      for (uint32_t omega = 0; omega < kPalettePhase1Omegas && !taken; ++omega) {
        const auto [k, l] = large[omega].largest(i, j);
        if ((uint64_t{1} << omega) * b + kPaletteDirBits < uint64_t{l - k}) {
          blocks.push_back({k, l});
          ranges.push_back({l, j});
          ranges.push_back({i, k});
          taken = true;
        }
      }
      if (!taken) remaining(i, j);
    }
  }
};

void derive_palette(ColourPalette& p) {
  p.palette_omega.resize(p.palettes());
  p.palette_bit.resize(p.palettes());
  uint64_t bit = 0;
  for (size_t q = 0; q < p.palettes(); ++q) {
    p.palette_omega[q] = static_cast<uint8_t>(palette_ceil_log2(p.palette_size[q]));
    p.palette_bit[q] = bit;
    bit += uint64_t{p.palette_size[q]} * p.material_bits;
  }
  p.block_bit.resize(p.blocks());
  bit = 0;
  for (size_t g = 0; g < p.blocks(); ++g) {
    p.block_bit[g] = bit;
    const uint64_t end = g + 1 < p.blocks() ? p.block_start[g + 1] : p.entries;
    bit += (end - p.block_start[g]) * p.palette_omega[p.block_palette[g]];
  }
}

struct PaletteSectionHead {
  uint64_t materials, palette_entries, index_bits, material_bits;
};
static_assert(sizeof(PaletteSectionHead) == 32);

}  // namespace

uint64_t ColourPalette::palette_entries() const {
  uint64_t n = 0;
  for (uint16_t s : palette_size) n += s;
  return n;
}

uint64_t ColourPalette::index_bits() const {
  if (blocks() == 0) return 0;
  const uint64_t last = blocks() - 1;
  return block_bit[last] + (entries - block_start[last]) * palette_omega[block_palette[last]];
}

std::array<uint8_t, 3> ColourPalette::colour(uint64_t i) const {
  const size_t g = static_cast<size_t>(std::upper_bound(block_start.begin(), block_start.end(), i) - block_start.begin()) - 1;
  const uint32_t q = block_palette[g];
  const uint64_t slot = palette_get_bits(index_words, block_bit[g] + (i - block_start[g]) * palette_omega[q], palette_omega[q]);
  const uint64_t mat = palette_get_bits(palette_words, palette_bit[q] + slot * material_bits, material_bits);
  return {materials[3 * mat], materials[3 * mat + 1], materials[3 * mat + 2]};
}

std::vector<uint8_t> ColourPalette::decode() const {
  std::vector<uint8_t> out(entries * 3);
  for (size_t g = 0; g < blocks(); ++g) {
    const uint32_t q = block_palette[g], omega = palette_omega[q];
    const uint64_t end = g + 1 < blocks() ? block_start[g + 1] : entries;
    uint64_t bit = block_bit[g];
    for (uint64_t i = block_start[g]; i < end; ++i, bit += omega) {
      const uint64_t mat =
          palette_get_bits(palette_words, palette_bit[q] + palette_get_bits(index_words, bit, omega) * material_bits, material_bits);
      std::memcpy(&out[3 * i], &materials[3 * mat], 3);
    }
  }
  return out;
}

ColourPalette palette_encode(std::span<const uint8_t> rgb) {
  const uint64_t n = rgb.size() / 3;
  if (n >= (uint64_t{1} << 32)) throw Error("palette compression takes fewer than 2^32 colours");
  ColourPalette p;
  p.entries = n;
  if (n == 0) return p;
  // The steps before the block search are independent per entry (or a sort), so they run on every core; the
  // result does not depend on how the work is split.
  auto each = [n](auto&& f) {
    tbb::parallel_for(tbb::blocked_range<uint64_t>(0, n, 1 << 16), [&](const tbb::blocked_range<uint64_t>& r) {
      for (uint64_t i = r.begin(); i < r.end(); ++i) f(i);
    });
  };
  // The materials are the distinct colours in ascending 0xRRGGBB order, and an entry's index its colour's rank
  // among them: a bit per possible colour (2 MiB) and the count of set bits before each word give both, where a
  // sort and a search per entry took several times longer.
  auto packed = [&](uint64_t i) { return uint32_t{rgb[3 * i]} << 16 | uint32_t{rgb[3 * i + 1]} << 8 | rgb[3 * i + 2]; };
  std::vector<uint64_t> seen(uint64_t{1} << 18, 0);
  each([&](uint64_t i) {
    const uint32_t c = packed(i);
    std::atomic_ref<uint64_t>(seen[c >> 6]).fetch_or(uint64_t{1} << (c & 63), std::memory_order_relaxed);
  });
  std::vector<uint32_t> before(seen.size());
  uint32_t lambda = 0;
  for (size_t w = 0; w < seen.size(); ++w) before[w] = lambda, lambda += static_cast<uint32_t>(std::popcount(seen[w]));
  std::vector<uint32_t> m(n);
  each([&](uint64_t i) {
    const uint32_t c = packed(i);
    m[i] = before[c >> 6] + static_cast<uint32_t>(std::popcount(seen[c >> 6] & ((uint64_t{1} << (c & 63)) - 1)));
  });
  p.material_bits = palette_ceil_log2(lambda);
  p.materials.resize(3 * uint64_t{lambda});
  for (size_t w = 0, k = 0; w < seen.size(); ++w)
    for (uint64_t bits = seen[w]; bits; bits &= bits - 1, ++k) {
      const uint32_t c = static_cast<uint32_t>(w << 6) | static_cast<uint32_t>(std::countr_zero(bits));
      for (int ch = 0; ch < 3; ++ch) p.materials[3 * k + ch] = static_cast<uint8_t>(c >> (16 - 8 * ch));
    }

  std::vector<std::pair<uint32_t, uint32_t>> found;
  {  // the search tables live only here
    PaletteSelection s{m, p.material_bits, {}, {}, {}};
    // the windows of each ω are independent scans of the same indices
    std::vector<std::vector<uint32_t>> ends(kPalettePhase2Omegas);
    tbb::parallel_for(uint32_t{0}, kPalettePhase2Omegas,
                      [&](uint32_t omega) { ends[omega] = palette_window_ends(m, lambda, 1u << omega); });
    for (uint32_t omega = 0; omega < kPalettePhase2Omegas; ++omega) {
      if (omega < kPalettePhase1Omegas) s.large.emplace_back(std::move(ends[omega]));
      else s.ends.push_back(std::move(ends[omega]));
    }
    s.large_blocks(static_cast<uint32_t>(n));
    found = std::move(s.blocks);
  }
  std::sort(found.begin(), found.end());

  // Palettes numbered by first use, blocks in order: the same bytes whatever order selection found them in.
  std::map<std::vector<uint32_t>, uint32_t> ids;
  std::vector<uint32_t> stamp(lambda, 0xffffffffu), entries_of;
  std::vector<std::vector<uint32_t>> palettes;
  for (uint32_t g = 0; g < found.size(); ++g) {
    const auto [k, l] = found[g];
    std::vector<uint32_t> set;
    for (uint32_t i = k; i < l; ++i)
      if (stamp[m[i]] != g) stamp[m[i]] = g, set.push_back(m[i]);
    std::sort(set.begin(), set.end());
    auto [it, fresh] = ids.emplace(set, static_cast<uint32_t>(palettes.size()));
    if (fresh) palettes.push_back(std::move(set));
    p.block_start.push_back(k);
    p.block_palette.push_back(it->second);
  }
  uint64_t pe = 0;
  for (const auto& q : palettes) {
    p.palette_size.push_back(static_cast<uint16_t>(q.size()));
    pe += q.size();
  }
  p.palette_words.assign(palette_words_for(pe * p.material_bits), 0);
  derive_palette(p);
  for (size_t q = 0; q < palettes.size(); ++q)
    for (size_t e = 0; e < palettes[q].size(); ++e)
      palette_put_bits(p.palette_words, p.palette_bit[q] + e * p.material_bits, palettes[q][e], p.material_bits);
  p.index_words.assign(palette_words_for(p.index_bits()), 0);
  std::vector<uint32_t> slot(lambda, 0);
  for (size_t g = 0; g < p.blocks(); ++g) {
    const std::vector<uint32_t>& q = palettes[p.block_palette[g]];
    for (uint32_t e = 0; e < q.size(); ++e) slot[q[e]] = e;
    const uint32_t omega = p.palette_omega[p.block_palette[g]];
    const auto [k, l] = found[g];
    for (uint32_t i = k; i < l; ++i) palette_put_bits(p.index_words, p.block_bit[g] + uint64_t{i - k} * omega, slot[m[i]], omega);
  }
  return p;
}

std::vector<uint8_t> palette_serialise(const ColourPalette& p) {
  const PaletteSectionHead head{p.materials_count(), p.palette_entries(), p.index_bits(), p.material_bits};
  const uint64_t mat_bytes = palette_pad8(p.materials.size()), size_bytes = palette_pad8(p.palettes());
  std::vector<uint8_t> out(sizeof head + mat_bytes + 8 * p.blocks() + size_bytes + 8 * p.palette_words.size() +
                           8 * p.index_words.size(), 0);
  uint8_t* at = out.data();
  std::memcpy(at, &head, sizeof head);
  at += sizeof head;
  if (!p.materials.empty()) std::memcpy(at, p.materials.data(), p.materials.size());
  at += mat_bytes;
  for (size_t g = 0; g < p.blocks(); ++g, at += 8) {
    std::memcpy(at, &p.block_start[g], 4);
    std::memcpy(at + 4, &p.block_palette[g], 4);
  }
  for (size_t q = 0; q < p.palettes(); ++q) at[q] = static_cast<uint8_t>(p.palette_size[q] - 1);
  at += size_bytes;
  if (!p.palette_words.empty()) std::memcpy(at, p.palette_words.data(), 8 * p.palette_words.size());
  at += 8 * p.palette_words.size();
  if (!p.index_words.empty()) std::memcpy(at, p.index_words.data(), 8 * p.index_words.size());
  return out;
}

ColourPalette palette_parse(std::span<const uint8_t> bytes, uint64_t entries, uint64_t blocks, uint64_t palettes) {
  auto fail = [](const std::string& why) { return Error("bad colour palette: " + why); };
  PaletteSectionHead head{};
  if (bytes.size() < sizeof head) throw fail("shorter than its head (" + std::to_string(bytes.size()) + " bytes)");
  std::memcpy(&head, bytes.data(), sizeof head);
  if (entries == 0 || entries >= (uint64_t{1} << 32)) throw fail(std::to_string(entries) + " entries (1 to 2^32 - 1)");
  if (blocks == 0 || blocks > entries || palettes == 0 || palettes > blocks)
    throw fail(std::to_string(blocks) + " blocks and " + std::to_string(palettes) + " palettes for " +
               std::to_string(entries) + " entries");
  if (head.materials == 0 || head.materials > entries || head.material_bits != palette_ceil_log2(head.materials))
    throw fail(std::to_string(head.materials) + " materials of " + std::to_string(head.material_bits) + " bits");
  if (head.palette_entries < palettes || head.palette_entries > 256 * palettes)
    throw fail(std::to_string(head.palette_entries) + " palette entries in " + std::to_string(palettes) + " palettes");
  if (head.index_bits > 8 * entries) throw fail(std::to_string(head.index_bits) + " index bits");
  // Every count is now below 2^43, so no size below overflows.
  ColourPalette p;
  p.entries = entries;
  p.material_bits = static_cast<uint32_t>(head.material_bits);
  const uint64_t mat_bytes = palette_pad8(3 * head.materials), size_bytes = palette_pad8(palettes);
  const uint64_t pal_words = palette_words_for(head.palette_entries * head.material_bits);
  const uint64_t idx_words = palette_words_for(head.index_bits);
  const uint64_t want = sizeof head + mat_bytes + 8 * blocks + size_bytes + 8 * pal_words + 8 * idx_words;
  if (bytes.size() != want)
    throw fail(std::to_string(bytes.size()) + " bytes where its counts make " + std::to_string(want));
  const uint8_t* at = bytes.data() + sizeof head;
  p.materials.assign(at, at + 3 * head.materials);
  if (std::any_of(at + 3 * head.materials, at + mat_bytes, [](uint8_t c) { return c != 0; })) throw fail("padding not zero");
  for (uint64_t k = 1; k < head.materials; ++k)
    if (std::memcmp(&p.materials[3 * (k - 1)], &p.materials[3 * k], 3) >= 0) throw fail("materials not strictly increasing");
  at += mat_bytes;
  p.block_start.resize(blocks);
  p.block_palette.resize(blocks);
  for (uint64_t g = 0; g < blocks; ++g, at += 8) {
    std::memcpy(&p.block_start[g], at, 4);
    std::memcpy(&p.block_palette[g], at + 4, 4);
    if (p.block_palette[g] >= palettes) throw fail("block " + std::to_string(g) + " names palette " + std::to_string(p.block_palette[g]));
    if (g == 0 ? p.block_start[g] != 0 : p.block_start[g] <= p.block_start[g - 1])
      throw fail("block " + std::to_string(g) + " starts at " + std::to_string(p.block_start[g]));
  }
  if (p.block_start.back() >= entries) throw fail("the last block starts past the entries");
  p.palette_size.resize(palettes);
  uint64_t pe = 0;
  for (uint64_t q = 0; q < palettes; ++q) pe += p.palette_size[q] = uint16_t{at[q]} + 1;
  if (std::any_of(at + palettes, at + size_bytes, [](uint8_t c) { return c != 0; })) throw fail("padding not zero");
  if (pe != head.palette_entries) throw fail("palette sizes sum to " + std::to_string(pe) + ", not " + std::to_string(head.palette_entries));
  at += size_bytes;
  p.palette_words.resize(pal_words);
  if (pal_words) std::memcpy(p.palette_words.data(), at, 8 * pal_words);
  at += 8 * pal_words;
  p.index_words.resize(idx_words);
  if (idx_words) std::memcpy(p.index_words.data(), at, 8 * idx_words);
  derive_palette(p);
  if (p.index_bits() != head.index_bits)
    throw fail("the blocks need " + std::to_string(p.index_bits()) + " index bits, not " + std::to_string(head.index_bits));
  auto tail_zero = [](const std::vector<uint64_t>& w, uint64_t bits) {
    return bits % 64 == 0 || (w.back() >> (bits % 64)) == 0;
  };
  if (!tail_zero(p.palette_words, pe * p.material_bits) || !tail_zero(p.index_words, head.index_bits))
    throw fail("padding bits not zero");
  for (uint64_t e = 0; e < pe; ++e)
    if (palette_get_bits(p.palette_words, e * p.material_bits, p.material_bits) >= head.materials)
      throw fail("palette entry " + std::to_string(e) + " past the " + std::to_string(head.materials) + " materials");
  for (uint64_t g = 0; g < blocks; ++g) {
    const uint32_t q = p.block_palette[g], omega = p.palette_omega[q];
    const uint64_t end = g + 1 < blocks ? p.block_start[g + 1] : entries;
    for (uint64_t i = 0; i < end - p.block_start[g]; ++i)
      if (palette_get_bits(p.index_words, p.block_bit[g] + i * omega, omega) >= p.palette_size[q])
        throw fail("entry " + std::to_string(p.block_start[g] + i) + " past its palette's " +
                   std::to_string(p.palette_size[q]) + " colours");
  }
  return p;
}

}  // namespace mv

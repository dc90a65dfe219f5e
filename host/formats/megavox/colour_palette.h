// megavox — lossless palette compression of a depth-first RGB24 attribute array (docs/colour.md), as Kol's
// thesis (ch. 2, Algorithm 1) describes it.
//
// The λ distinct colours form the material array M (sorted by 0xRRGGBB value); every entry becomes an index into
// M. The index array is split into variable-length blocks of consecutive entries. Each block names one palette
// (a sorted list of material indices, 1 to 256 of them, shared by every block with the same set) and stores one
// ω-bit palette index per entry, ω = ceil(log2 palette size). A directory of block starts, in increasing order,
// finds the block of an entry by binary search. Selection runs on the host: Algorithm 1 is sequential (it
// recurses on what its largest blocks leave), and the result depends only on the colours, so it is the same
// bytes on every run.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace mv {

struct ColourPalette {
  uint64_t entries = 0;             // Λ: the attribute array's length
  uint32_t material_bits = 0;       // ceil(log2 λ): the width of a palette entry
  std::vector<uint8_t> materials;   // λ colours, 3 bytes each (R first), sorted by 0xRRGGBB
  std::vector<uint32_t> block_start;    // the directory: first entry of each block, strictly increasing, [0] = 0
  std::vector<uint32_t> block_palette;  // the directory: each block's palette
  std::vector<uint16_t> palette_size;   // entries of each palette, 1 .. 256
  std::vector<uint64_t> palette_words;  // the palettes' material indices, material_bits each, packed LSB first
  std::vector<uint64_t> index_words;    // the blocks' palette indices, ω bits each, packed LSB first
  // Derived when encoded or parsed (not stored): where each palette and each block starts, in bits.
  std::vector<uint64_t> palette_bit, block_bit;
  std::vector<uint8_t> palette_omega;

  uint64_t blocks() const { return block_start.size(); }
  uint64_t palettes() const { return palette_size.size(); }
  uint64_t materials_count() const { return materials.size() / 3; }
  uint64_t palette_entries() const;
  uint64_t index_bits() const;
  // The colour of entry i (< entries): the directory's binary search, then the block's palette.
  std::array<uint8_t, 3> colour(uint64_t i) const;
  // Every entry, RGB24 in order.
  std::vector<uint8_t> decode() const;
};

// Algorithm 1 on `rgb` (3 bytes per entry, fewer than 2^32 entries). Deterministic.
ColourPalette palette_encode(std::span<const uint8_t> rgb);

// The stored form: a 32-byte palette head (materials, palette entries, index bits, material bits), the
// materials (3 bytes each, zero padding to 8 bytes), the directory (start, palette: 2 x uint32 per block), the
// palette sizes minus one (1 byte each, zero padding to 8 bytes), then the palette words and the index words.
std::vector<uint8_t> palette_serialise(const ColourPalette& p);
// Parses and checks every field against `entries`, `blocks` and `palettes` (which the caller's head holds):
// sizes, the directory's order, every material index < λ and every palette index < its palette's size, padding
// zero. Throws mv::Error saying what is wrong (the caller names the file).
ColourPalette palette_parse(std::span<const uint8_t> bytes, uint64_t entries, uint64_t blocks, uint64_t palettes);

}  // namespace mv

/* A hit's colour (docs/colour.md), written once for the host, OpenCL C and GLSL. The colours are one per octree
 * node in depth-first order, so a hit's colour is entry index(cell), where the index comes from a walk from the
 * root down to the hit's cell: a child's index is its parent's + 1 + the subtree sizes of its earlier siblings in
 * the order the walk sees them (mirrored where a pointer's tag says so). The walk reads the same node words as the
 * traversal (trace_nodes.h) plus one 32-bit subtree size per inner node above the leaves' parents (the `meta`
 * buffer); the sizes of the nodes two levels above the voxels come from their own masks.
 *
 * It runs after the trace, once per hit, and leaves the trace loop as it is: a render without colour pays
 * nothing, and the walk's cost (at most L levels of 8 sibling sizes) is paid only where a ray hit. */
#ifndef MV_TRACE_COLOUR_H
#define MV_TRACE_COLOUR_H
#include "trace_nodes.h"

/* meta: where the level starts lie (index = level, ssvdag: in 16-bit words of the inner stream; zeros for the
 * word encodings), then from MV_COLOUR_SIZES_AT(L) one subtree size per stream position: per 32-bit word for the
 * word encodings, per 16-bit word of the inner stream for an ssvdag; only node starts of levels >= 3 are read. */
#define MV_COLOUR_SIZES_AT(L) ((L) + 1u)
#define MV_COLOUR_ALPHA 0xff000000u /* a hit's colour word: R | G << 8 | B << 16 | 255 << 24; a miss: 0 */

/* The colours buffer: a head of MV_COLOUR_HEAD words, word 0 the format. MV_COLOUR_RAW: from the head on, one
 * R | G << 8 | B << 16 word per entry. MV_COLOUR_PALETTE (Kol's Algorithm 1 as the .mvx stores it, docs/colour.md):
 * the head's words are the format, the blocks, the material bits and where five arrays start: the directory (each
 * block's first entry), per block its palette, its first index bit and ω, per palette its first bit in the
 * palette words, the materials (one colour word each), the palette words and the index words (each a run of
 * 32-bit words, LSB first, with a spare word after it). */
#define MV_COLOUR_HEAD 10u
#define MV_COLOUR_RAW 0u
#define MV_COLOUR_PALETTE 1u
#define MV_COLOUR_AT_DIRECTORY 3u
#define MV_COLOUR_AT_BLOCKS 4u
#define MV_COLOUR_AT_PALETTES 5u
#define MV_COLOUR_AT_MATERIALS 6u
#define MV_COLOUR_AT_PALETTE_WORDS 7u
#define MV_COLOUR_AT_INDEX_WORDS 8u

/* `width` (< 32) bits from bit `at` of the words starting at word `base`. */
MV_INLINE mv_u32 mv_colour_bits(MvBufU32 c, mv_u32 base, mv_u32 at, mv_u32 width) {
  mv_u32 w = base + (at >> 5);
  mv_u64 v = (MV_U64(MV_LD(c, w + 1u)) << 32) | MV_U64(MV_LD(c, w));
  return MV_U32(v >> (at & 31u)) & ((1u << width) - 1u);
}

/* Entry e's colour word (R | G << 8 | B << 16): raw, or through the directory's binary search, the block's palette
 * and the materials. */
MV_INLINE mv_u32 mv_colour_entry(MvBufU32 c, mv_u32 e) {
  if (MV_LD(c, 0u) == MV_COLOUR_RAW) return MV_LD(c, MV_COLOUR_HEAD + e);
  mv_u32 dir = MV_LD(c, MV_COLOUR_AT_DIRECTORY);
  mv_u32 lo = 0u, hi = MV_LD(c, 1u); /* the last block whose first entry is <= e */
  while (hi - lo > 1u) {
    mv_u32 mid = lo + (hi - lo) / 2u;
    if (MV_LD(c, dir + mid) <= e) lo = mid;
    else hi = mid;
  }
  mv_u32 blk = MV_LD(c, MV_COLOUR_AT_BLOCKS) + 3u * lo;
  mv_u32 omega = MV_LD(c, blk + 2u);
  mv_u32 slot = mv_colour_bits(c, MV_LD(c, MV_COLOUR_AT_INDEX_WORDS), MV_LD(c, blk + 1u) + (e - MV_LD(c, dir + lo)) * omega,
                               omega);
  mv_u32 mbits = MV_LD(c, 2u);
  mv_u32 at = MV_LD(c, MV_LD(c, MV_COLOUR_AT_PALETTES) + MV_LD(c, blk)) + slot * mbits;
  mv_u32 material = mv_colour_bits(c, MV_LD(c, MV_COLOUR_AT_PALETTE_WORDS), at, mbits);
  return MV_LD(c, MV_LD(c, MV_COLOUR_AT_MATERIALS) + material);
}

/* The subtree size of an ssvdag brick (a level-2 node): itself, its full 2^3 sub-blocks and its voxels. */
MV_INLINE mv_u32 mv_brick_size(mv_u32 lo, mv_u32 hi) {
  return 1u + MV_POPCOUNT(mv_brick_occupancy(lo, hi)) + MV_POPCOUNT(lo) + MV_POPCOUNT(hi);
}

/* What a colour walk to level lc sees at level l: the octant of cell (x, y, z) below it, and its full slots (a
 * node's; in an ssvdag brick, the brick's at level 2 and sub-block `node`'s at level 1). */
MV_INLINE mv_u32 mv_colour_octant(mv_u32 x, mv_u32 y, mv_u32 z, mv_u32 l, mv_u32 lc) {
  mv_u32 sh = l - 1u - lc;
  return ((x >> sh) & 1u) | (((y >> sh) & 1u) << 1) | (((z >> sh) & 1u) << 2);
}

MV_INLINE mv_u32 mv_colour_occupancy(mv_u32 enc, mv_u32 l, mv_u32 hdr, mv_u32 lo, mv_u32 hi, mv_u32 node) {
  if (!(mv_enc_compact(enc) && l <= 2u)) return mv_node_occupancy(enc, hdr);
  return l == 2u ? mv_brick_occupancy(lo, hi) : mv_sub_block_occupancy(lo, hi, node);
}

/* One stored child of a node: where it is (a word; an ssvdag inner node: a 16-bit word of its level's start +
 * offset; a brick: its number), its mirror tag, and its subtree size. */
MV_STRUCT_BEGIN(MvColourChild)
  mv_u32 at;
  mv_u32 tag;
  mv_u32 size;
MV_STRUCT_END(MvColourChild)

/* Stored child `v` (Morton) of the node `node` (header `hdr`) of level l >= 2. Word encodings: level 2's
 * children are one-word leaves sized by their masks. ssvdag: l >= 3 (bricks are handled by the caller). */
MV_INLINE MvColourChild mv_colour_child(MvBufU32 words, MvBufU32 bricks, MvBufU32 meta, mv_u32 enc, mv_u32 L,
                                        mv_u32 l, mv_u32 node, mv_u32 hdr, mv_u32 v) {
  MvColourChild c;
  mv_u32 t8 = mv_xmajor_octant(v);
  if (!mv_enc_compact(enc)) {
    c.at = MV_LD(words, mv_word_child_at(node, hdr, t8));
    c.tag = mv_word_child_tag(hdr, t8);
    c.size = l == 2u ? 1u + MV_POPCOUNT(MV_LD(words, c.at) & 0xffu) : MV_LD(meta, MV_COLOUR_SIZES_AT(L) + c.at);
    return c;
  }
  mv_u32 at = mv_ssvdag_child_at(node, hdr, t8);
  mv_u32 ptr = mv_inner_words(mv_node_load(words, bricks, enc, l, at), at);
  mv_u32 off = mv_ssvdag_offset(ptr, mv_ssvdag_child_code(hdr, t8));
  c.tag = mv_ssvdag_tag(ptr);
  if (l == 3u) {
    c.at = off;
    c.size = mv_brick_size(MV_LD(bricks, 2u * off), MV_LD(bricks, 2u * off + 1u));
  } else {
    c.at = MV_LD(meta, l - 1u) + off;
    c.size = MV_LD(meta, MV_COLOUR_SIZES_AT(L) + c.at);
  }
  return c;
}

/* The depth-first index of the cell (x, y, z) of level lc in a DAG of L levels (the cell is full: a hit). */
MV_INLINE mv_u32 mv_hit_attribute(MvBufU32 words, MvBufU32 bricks, MvBufU32 meta, mv_u32 enc, mv_u32 L,
                                  mv_u32 x, mv_u32 y, mv_u32 z, mv_u32 lc) {
  mv_u32 index = 0u;
  mv_u32 node = 0u; /* the root: word 0, or the inner stream's 16-bit word 0 */
  mv_u32 hdr = mv_enc_compact(enc) ? mv_inner_word(mv_node_load(words, bricks, enc, L, 0u), 0u) : MV_LD(words, 0u);
  mv_u32 lo = 0u, hi = 0u; /* ssvdag: the brick, once the walk is in one */
  mv_u32 mir = 0u;
  for (mv_u32 l = L; l > lc; --l) {
    mv_u32 a = mv_colour_octant(x, y, z, l, lc); /* the octant as seen */
    bool in_brick = mv_enc_compact(enc) && l <= 2u;
    mv_u32 occ = mv_colour_occupancy(enc, l, hdr, lo, hi, node);
    mv_u32 skip = 1u;
    mv_u32 next = 0u, next_tag = 0u;
    for (mv_u32 b = 0u; b < 8u; ++b) {
      mv_u32 v = b ^ mir;
      if (b > a || ((occ >> v) & 1u) == 0u) continue;
      mv_u32 size = 1u, at = v, tag = 0u;
      if (l == 2u && in_brick) {
        size = 1u + MV_POPCOUNT(mv_sub_block_occupancy(lo, hi, v));
      } else if (l >= 2u) {
        MvColourChild c = mv_colour_child(words, bricks, meta, enc, L, l, node, hdr, v);
        size = c.size;
        at = c.at;
        tag = c.tag;
      }
      if (b < a) skip += size;
      else {
        next = at;
        next_tag = tag;
      }
    }
    index += skip;
    /* into the child: its words (a brick's halves once at level 2; a sub-block keeps the brick and its slot) */
    mir = mir ^ next_tag;
    node = next;
    if (mv_enc_compact(enc) && l == 3u) {
      lo = MV_LD(bricks, 2u * next);
      hi = MV_LD(bricks, 2u * next + 1u);
    } else if (!(mv_enc_compact(enc) && l <= 2u) && l >= 2u) {
      mv_u64 data = mv_node_load(words, bricks, enc, l - 1u, next);
      hdr = mv_enc_compact(enc) ? mv_inner_word(data, next) : MV_U32(data);
    }
  }
  return index;
}

#if !defined(MV_CPP)
/* One work-item's share of hits [p.first, p.first + p.count): each hit's colour word (MV_COLOUR_ALPHA set) from
 * `colours` (raw or palette, see MV_COLOUR_HEAD), 0 for a miss. The levels come from p.mode. */
MV_INLINE void mv_hit_colours(MvBufU32 hits, MvBufU32 words, MvBufU32 bricks, MvBufU32 meta, MvBufU32 colours,
                              MvBufU32 colour_out, MvTraceParams p, mv_u32 gid, mv_u32 gsize, mv_u32 enc) {
  const mv_u32 L = MV_TRACE_LEVELS(p);
  for (mv_u32 j = gid; j < p.count; j += gsize) {
    mv_u32 i = p.first + j;
    MvHit h = mv_load_hit(hits, i);
    mv_u32 rgba = 0u;
    if (MV_INFO_STATUS(h.info) == MV_TRACE_HIT) {
      mv_u32 e = mv_hit_attribute(words, bricks, meta, enc, L, h.x, h.y, h.z, MV_INFO_LEVEL(h.info));
      rgba = mv_colour_entry(colours, e) | MV_COLOUR_ALPHA;
    }
    MV_ST(colour_out, i, rgba);
  }
}
#endif

#endif /* MV_TRACE_COLOUR_H */

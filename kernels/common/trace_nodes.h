/* Node decoding for ray traversal (trace.h): what the walk reads of each encoded node, written once for the
 * host, OpenCL C and GLSL.
 *
 * Encodings (include/megavox/encode.h): svo / svdag / ussvdag are one stream of 32-bit words (header word with
 * the child mask and, for ussvdag, per-child mirror bits; one 32-bit pointer per child, absolute or, paged in
 * level order, counting from its child level's start; one-word 2^3 leaves); ssvdag is the compact stream of
 * 16-bit words (2-bit child codes, 16/32-bit pointers with mirror tags, offsets relative to the child level)
 * over 64-bit 4^3 bricks. */
#ifndef MV_TRACE_NODES_H
#define MV_TRACE_NODES_H
#include "trace_types.h"

/* X-major octant index (4x + 2y + z, the order encoded nodes keep their children in) of a Morton octant
 * (x + 2y + 4z); its own inverse. */
MV_INLINE mv_u32 mv_xmajor_octant(mv_u32 m) { return ((m & 1u) << 2) | (m & 2u) | ((m >> 2) & 1u); }

/* The compact ssvdag decode (resident or paged), and reads through the page cache (either encoding family):
 * constants of each entry point, so each kernel compiles only its own path. */
MV_INLINE bool mv_enc_compact(mv_u32 enc) { return enc == MV_ENC_SSVDAG || enc == MV_ENC_PAGED_SSVDAG; }
MV_INLINE bool mv_enc_paged(mv_u32 enc) { return enc == MV_ENC_PAGED || enc == MV_ENC_PAGED_SSVDAG; }

/* The walk's one read of the node streams: every header, pointer and brick it reads comes from here, by the
 * level of the node read, so a paged address layer can take its place. 32-bit word encodings: word `addr`.
 * ssvdag inner levels (lv > 2; 16-bit words stored two per 32-bit word, low half first): the two 32-bit words
 * from the one holding 16-bit word `addr`, so a header or both words of a pointer come in one read (any
 * parity; the stream ends with a spare word); ssvdag level 2: brick `addr`, low half first. One load whatever
 * the level: buffer and index are picked by selects, as lavapipe pays per load instruction (see trace.h).
 * A paged ssvdag reads both from the cache's slots: inner nodes at 16-bit word `addr`, bricks at 32-bit word
 * `addr` (the slots end with spare words). */
MV_INLINE mv_u64 mv_node_load(MvBufU32 words, MvBufU32 bricks, mv_u32 enc, mv_u32 lv, mv_u32 addr) {
  if (!mv_enc_compact(enc)) return MV_U64(MV_LD(words, addr));
  bool inner = lv > 2u;
  if (enc == MV_ENC_PAGED_SSVDAG) return MV_LD_PAIR(words, inner ? addr >> 1 : addr);
  return MV_LD_PAIR(inner ? words : bricks, inner ? addr >> 1 : 2u * addr);
}

/* Of an ssvdag inner-level read at `addr` (mv_node_load): the 16-bit word at addr (a header), and the 16-bit
 * words addr and addr + 1 as one 32-bit value, addr's in the low half (a pointer). */
MV_INLINE mv_u32 mv_inner_word(mv_u64 data, mv_u32 addr) { return (MV_U32(data) >> ((addr & 1u) * 16u)) & 0xffffu; }
MV_INLINE mv_u32 mv_inner_words(mv_u64 data, mv_u32 addr) { return MV_U32(data >> ((addr & 1u) * 16u)); }

/* 32-bit word encodings: where the pointer to x-major child t8 of the node at word `node` is (the pointers
 * follow the header in descending child order), and that child's mirror tag (ussvdag header bits 8 + t8,
 * 16 + t8, 24 + t8 for x, y, z). */
MV_INLINE mv_u32 mv_word_child_at(mv_u32 node, mv_u32 hdr, mv_u32 t8) {
  return node + 1u + MV_POPCOUNT((hdr & 0xffu) >> (t8 + 1u));
}

MV_INLINE mv_u32 mv_word_child_tag(mv_u32 hdr, mv_u32 t8) {
  return ((hdr >> (8u + t8)) & 1u) | (((hdr >> (16u + t8)) & 1u) << 1) | (((hdr >> (24u + t8)) & 1u) << 2);
}

/* ssvdag inner node at 16-bit word `node`: x-major child t8's 2-bit code, and where its pointer is: 1 + the sum
 * over later children of min(code, 2) (bit 2k of the OR counts code k != 0, bit 2k + 1 code k >= 2). */
MV_INLINE mv_u32 mv_ssvdag_child_code(mv_u32 hdr, mv_u32 t8) { return (hdr >> (2u * t8)) & 3u; }

MV_INLINE mv_u32 mv_ssvdag_child_at(mv_u32 node, mv_u32 hdr, mv_u32 t8) {
  mv_u32 later = hdr >> (2u * (t8 + 1u));
  return node + 1u + MV_POPCOUNT(((later | (later >> 1)) & 0x5555u) | (later & 0xaaaau));
}

/* An ssvdag pointer from its two 16-bit words w (mv_inner_words) and its child's code: code 1 is one word, the
 * mirror tag in bits 15..13 and a 13-bit offset; codes 2 and 3 are two words, high first, the tag in bits
 * 31..29, offset bits 28..0 and offset bit 29 = code & 1. Either way the tag leads the first word. Offsets
 * count from the start of the child's level (16-bit words; bricks for a brick). */
MV_INLINE mv_u32 mv_ssvdag_offset(mv_u32 w, mv_u32 code) {
  mv_u32 first = w & 0xffffu;
  return code == 1u ? first & 0x1fffu : ((((first << 16) | (w >> 16)) & 0x1fffffffu) | ((code & 1u) << 29));
}

MV_INLINE mv_u32 mv_ssvdag_tag(mv_u32 w) { return (w & 0xffffu) >> 13; }

/* x with the bits under mask m and those s above them exchanged (a delta swap). */
MV_INLINE mv_u32 mv_delta_swap(mv_u32 x, mv_u32 m, mv_u32 s) {
  mv_u32 t = ((x >> s) ^ x) & m;
  return x ^ t ^ (t << s);
}

/* A node's 8 children as a mask over stored Morton slots (bit v = slot v full), computed once when the walk
 * enters the node, so each step tests one bit whatever the encoding or level. */

/* An 8-bit child mask from x-major octant order (bit 4x + 2y + z) to Morton order (bit x + 2y + 4z), and back
 * (mv_xmajor_octant on every bit): swap bits 1 <-> 4 and 3 <-> 6. */
MV_INLINE mv_u32 mv_xmajor_mask(mv_u32 h) {
  mv_u32 x = ((h >> 3) ^ h) & 0x0au;
  return (h ^ x ^ (x << 3)) & 0xffu;
}

/* 32-bit word encodings: the child mask in the header's low byte. ssvdag inner nodes: 2-bit codes, 0 = empty. */
MV_INLINE mv_u32 mv_node_occupancy(mv_u32 enc, mv_u32 hdr) {
  if (!mv_enc_compact(enc)) return mv_xmajor_mask(hdr & 0xffu);
  /* bit 2k (k = 4x + 2y + z): code k != 0; the x = 1 byte onto the odd bits gives bit x + 2z + 4y; then swap
   * the y and z bits (2 <-> 4, 3 <-> 5) for x + 2y + 4z */
  mv_u32 nz = (hdr | (hdr >> 1)) & 0x5555u;
  return mv_delta_swap((nz & 0x55u) | ((nz >> 7) & 0xaau), 0x0cu, 2u);
}

/* An ssvdag 4^3 brick (bit 16x + 4y + z) is held as two 32-bit halves: lo has x in {0, 1}, hi x in {2, 3}.
 * Sub-block v (x in {2v_x, 2v_x + 1}, ...) lies in half v_x and is full when any of its 8 bits is: OR the z,
 * y and x pairs onto each block's low corner (bit 8v_y + 2v_z of the half), put the hi half's corners one bit
 * up (bit v_x + 2v_z + 8v_y), close the gap (v_x + 2v_z + 4v_y) and swap the y and z bits. Straight-line
 * 32-bit code: no per-lane loop or 64-bit lanes on SIMD devices. */
MV_INLINE mv_u32 mv_half_corners(mv_u32 h) {
  mv_u32 t = h | (h >> 1);
  t = t | (t >> 4);
  return (t | (t >> 16)) & 0x0505u;
}

MV_INLINE mv_u32 mv_brick_occupancy(mv_u32 lo, mv_u32 hi) {
  mv_u32 u = mv_half_corners(lo) | (mv_half_corners(hi) << 1);
  return mv_delta_swap((u & 0x0fu) | ((u >> 4) & 0xf0u), 0x0cu, 2u);
}

/* The 2^3 sub-block `sub` of a brick: its voxels by slot. Its bits sit at 16x + 4y + z above the block's
 * corner; the x = 1 ones move down beside them (bit z + 2x + 4y), then two delta swaps give x + 2y + 4z. */
MV_INLINE mv_u32 mv_sub_block_occupancy(mv_u32 lo, mv_u32 hi, mv_u32 sub) {
  mv_u32 g = (((sub & 1u) != 0u ? hi : lo) >> (8u * ((sub >> 1) & 1u) + 2u * (sub >> 2))) & 0x330033u;
  return mv_delta_swap(mv_delta_swap((g | (g >> 14)) & 0xffu, 0x22u, 1u), 0x0cu, 2u);
}

/* Where ssvdag level lv (3 <= lv < 3 + n) starts, taken from the parameters by a chain of selects: no load and
 * no indexed array, for lavapipe (see trace.h; an index into the parameter array would put it in per-lane
 * scratch memory there). n, a constant: how many level starts the parameters carry (MV_TRACE_PARAM_LEVELS
 * resident, MV_TRACE_PAGED_PARAM_LEVELS paged). */
MV_INLINE mv_u32 mv_params_level_base(MvTraceParams p, mv_u32 lv, mv_u32 n) {
  mv_u32 b = p.level_base[0];
  b = lv == 4u ? p.level_base[1] : b;
  b = lv == 5u ? p.level_base[2] : b;
  b = lv == 6u ? p.level_base[3] : b;
  b = lv == 7u ? p.level_base[4] : b;
  b = lv == 8u ? p.level_base[5] : b;
  b = lv == 9u ? p.level_base[6] : b;
  b = lv == 10u ? p.level_base[7] : b;
  b = lv == 11u ? p.level_base[8] : b;
  b = lv == 12u ? p.level_base[9] : b;
  b = lv == 13u ? p.level_base[10] : b;
  if (n > 11u) {
    b = lv == 14u ? p.level_base[11] : b;
    b = lv == 15u ? p.level_base[12] : b;
  }
  return b;
}

/* Where resident ssvdag level lv (3 <= lv < L) starts in the inner stream (16-bit words): read from the
 * level-offset buffer (in_params = 0: one cached load, the cheapest where loads are cheap), or taken from the
 * parameters (in_params = 1, trees up to 64K^3). */
MV_INLINE mv_u32 mv_level_base(MvTraceParams p, MvBufU32 lvl_off, mv_u32 lv, mv_u32 in_params) {
  if (in_params == 0u) return MV_LD(lvl_off, lv);
  return mv_params_level_base(p, lv, MV_TRACE_PARAM_LEVELS);
}

/* Can the parameters hold where every level of a tree of L levels starts (mv_level_base's in_params)? Paged,
 * two of their words hold the cache's (MV_TRACE_PAGE_STAMP). */
MV_INLINE bool mv_trace_params_hold_levels(mv_u32 L, bool paged) {
  return L <= 3u + (paged ? MV_TRACE_PAGED_PARAM_LEVELS : MV_TRACE_PARAM_LEVELS);
}

#endif /* MV_TRACE_NODES_H */

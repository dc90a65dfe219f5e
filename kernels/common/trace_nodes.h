/* Node decoding for ray traversal (trace.h): what the walk reads of each encoded node, written once for the
 * host, OpenCL C and GLSL.
 *
 * Encodings (include/megavox/encode.h): svo / svdag / ussvdag are one stream of 32-bit words (header word with
 * the child mask and, for ussvdag, per-child mirror bits; one 32-bit absolute pointer per child; one-word 2^3
 * leaves); ssvdag is the compact stream of 16-bit words (2-bit child codes, 16/32-bit pointers with mirror
 * tags, offsets relative to the child level) over 64-bit 4^3 bricks. */
#ifndef MV_TRACE_NODES_H
#define MV_TRACE_NODES_H
#include "trace_types.h"

/* Thesis octant index (4x + 2y + z) of a Morton octant (x + 2y + 4z); its own inverse. */
MV_INLINE mv_u32 mv_thesis_octant(mv_u32 m) { return ((m & 1u) << 2) | (m & 2u) | ((m >> 2) & 1u); }

/* 16-bit word w of the ssvdag inner stream, stored two per 32-bit word, low half first. */
MV_INLINE mv_u32 mv_inner16(MvBufU32 words, mv_u32 w) { return (MV_LD(words, w >> 1) >> ((w & 1u) * 16u)) & 0xffffu; }

/* x with the bits under mask m and those s above them exchanged (a delta swap). */
MV_INLINE mv_u32 mv_delta_swap(mv_u32 x, mv_u32 m, mv_u32 s) {
  mv_u32 t = ((x >> s) ^ x) & m;
  return x ^ t ^ (t << s);
}

/* A node's 8 children as a mask over stored Morton slots (bit v = slot v full), computed once when the walk
 * enters the node, so each step tests one bit whatever the encoding or level. */

/* Thesis octant order (bit 4x + 2y + z) to Morton order (bit x + 2y + 4z): swap bits 1 <-> 4 and 3 <-> 6. */
MV_INLINE mv_u32 mv_thesis_to_morton_mask(mv_u32 h) {
  mv_u32 x = ((h >> 3) ^ h) & 0x0au;
  return (h ^ x ^ (x << 3)) & 0xffu;
}

/* 32-bit word encodings: the child mask in the header's low byte. ssvdag inner nodes: 2-bit codes, 0 = empty. */
MV_INLINE mv_u32 mv_node_occupancy(mv_u32 enc, mv_u32 hdr) {
  if (enc != MV_ENC_SSVDAG) return mv_thesis_to_morton_mask(hdr & 0xffu);
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

/* Where ssvdag level lv (3 <= lv < L) starts in the inner stream (16-bit words): read from the level-offset
 * buffer (in_params = 0: one cached load, the cheapest where loads are cheap), or taken from the parameters by
 * a chain of selects (in_params = 1, trees up to 16K^3: no load and no indexed array, for lavapipe, see the
 * top; an index into the parameter array would put it in per-lane scratch memory there). */
MV_INLINE mv_u32 mv_level_base(MvTraceParams p, MvBufU32 lvl_off, mv_u32 lv, mv_u32 in_params) {
  if (in_params == 0u) return MV_LD(lvl_off, lv);
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
  return b;
}

/* Can the parameters hold where every level of a tree of L levels starts (mv_level_base's in_params)? */
MV_INLINE bool mv_trace_params_hold_levels(mv_u32 L) { return L <= 3u + MV_TRACE_PARAM_LEVELS; }

#endif /* MV_TRACE_NODES_H */

/* The colour quantizer's per-colour step on the device (docs/colour.md, "Quantization"), written once for the
 * host, OpenCL C and GLSL: each distinct colour's nearest palette centre in CIELAB, a Lloyd round of the k-means.
 * The host keeps the median cut that seeds the centres and each round's means (per-centre arithmetic).
 *
 * The centres sit in a k-d tree laid out in an array (colour_quantize.h, centre_tree_order): the subtree over
 * order[lo, hi) has its root at order[mid], mid = lo + (hi - lo) / 2, splits on its axis (the depth mod 3) and
 * has [lo, mid) and [mid + 1, hi) below. A work-item per colour walks it depth first, the near side first and a
 * far side only while the splitting plane is no further than the best so far, starting from the colour's last
 * centre: the nearest centre by squared distance (doubles, as written, no contraction), the lowest index among
 * equals. The host's walk (the reference) visits the same nodes in the same order, so the answers are its own. */
#ifndef MV_QUANTIZE_H
#define MV_QUANTIZE_H
#include "mv_lang.h"

/* Pending subtrees of one walk: at most two per level (the far side waiting, the near side), and a tree over
 * fewer than 2^24 centres (--colour-bits below 24) has 24 levels. */
#define MV_QUANTIZE_STACK 50u

MV_STRUCT_BEGIN(MvQuantizeParams)
  mv_u32 n;       /* distinct colours */
  mv_u32 centres; /* palette centres */
  mv_u32 spare0;
  mv_u32 spare1;
MV_STRUCT_END(MvQuantizeParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvQuantizeParams, 16);
MV_LAYOUT_AT(MvQuantizeParams, n, 0); MV_LAYOUT_AT(MvQuantizeParams, centres, 4);
#endif

/* Squared CIELAB distance of (q0, q1, q2) to centre c (`centres`: L, a, b per centre). */
MV_INLINE mv_f64 mv_quantize_distance2(MvBufF64 centres, mv_u32 c, mv_f64 q0, mv_f64 q1, mv_f64 q2) {
  MV_PRECISE mv_f64 d0 = MV_LD(centres, 3u * c) - q0;
  MV_PRECISE mv_f64 d1 = MV_LD(centres, 3u * c + 1u) - q1;
  MV_PRECISE mv_f64 d2 = MV_LD(centres, 3u * c + 2u) - q2;
  MV_PRECISE mv_f64 d = d0 * d0 + d1 * d1 + d2 * d2;
  return d;
}

/* Colours [0, p.n) (`lab`: L, a, b each): `cluster` (its last centre on entry) becomes the nearest of the
 * p.centres centres; `moved` word 0 is set to 1 if any colour changed centre. */
MV_INLINE void mv_quantize_nearest(MvBufF64 lab, MvBufF64 centres, MvBufU32 order, MvBufU32 cluster, MvBufU32 moved,
                                   MvQuantizeParams p, mv_u32 gid, mv_u32 gsize) {
  for (mv_u32 i = gid; i < p.n; i += gsize) {
    mv_f64 q0 = MV_LD(lab, 3u * i), q1 = MV_LD(lab, 3u * i + 1u), q2 = MV_LD(lab, 3u * i + 2u);
    mv_u32 last = MV_LD(cluster, i), best = last;
    mv_f64 d = mv_quantize_distance2(centres, best, q0, q1, q2);
    /* An entry: its range, its axis (2 bits above lo's 30), and 1 + the node whose plane bounds it (0: none). */
    mv_u32 s_lo[MV_QUANTIZE_STACK];
    mv_u32 s_hi[MV_QUANTIZE_STACK];
    mv_u32 s_plane[MV_QUANTIZE_STACK];
    mv_u32 top = 1u;
    s_lo[0] = 0u;
    s_hi[0] = p.centres;
    s_plane[0] = 0u;
    while (top > 0u) {
      top = top - 1u;
      mv_u32 lo = s_lo[top] & 0x3fffffffu, axis = s_lo[top] >> 30, hi = s_hi[top], plane = s_plane[top];
      if (lo >= hi) continue;
      if (plane != 0u) { /* a far side: the plane of its parent (whose axis precedes this one) against the best */
        mv_u32 pa = axis == 0u ? 2u : axis - 1u;
        MV_PRECISE mv_f64 diff = (pa == 0u ? q0 : pa == 1u ? q1 : q2) - MV_LD(centres, 3u * (plane - 1u) + pa);
        MV_PRECISE mv_f64 diff2 = diff * diff;
        if (!(diff2 <= d)) continue;
      }
      mv_u32 mid = lo + (hi - lo) / 2u, at = MV_LD(order, mid);
      mv_f64 here = mv_quantize_distance2(centres, at, q0, q1, q2);
      if (here < d || (here == d && at < best)) {
        best = at;
        d = here;
      }
      MV_PRECISE mv_f64 split = (axis == 0u ? q0 : axis == 1u ? q1 : q2) - MV_LD(centres, 3u * at + axis);
      mv_u32 next = axis == 2u ? 0u : axis + 1u;
      /* the far side waits below the near side, which is walked first */
      mv_u32 near_lo = split < 0.0 ? lo : mid + 1u, near_hi = split < 0.0 ? mid : hi;
      mv_u32 far_lo = split < 0.0 ? mid + 1u : lo, far_hi = split < 0.0 ? hi : mid;
      if (top + 2u <= MV_QUANTIZE_STACK) {
        s_lo[top] = far_lo | (next << 30);
        s_hi[top] = far_hi;
        s_plane[top] = at + 1u;
        s_lo[top + 1u] = near_lo | (next << 30);
        s_hi[top + 1u] = near_hi;
        s_plane[top + 1u] = 0u;
        top = top + 2u;
      }
    }
    MV_ST(cluster, i, best);
    if (best != last) MV_ST(moved, 0u, 1u);
  }
}

#endif /* MV_QUANTIZE_H */

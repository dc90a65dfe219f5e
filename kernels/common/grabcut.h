/* GrabCut's per-pixel work (host/core/mask/grabcut.cpp drives it; docs/masks.md, "Exact GrabCut"), a pixel per
 * work-item of 1-D grid-stride launches. Every output is the same bits on every device: integers, or doubles
 * from + - * and floor in a fixed order (grabcut_math.h). The sums the host needs are in grabcut_sums.h.
 *   grabcut_colours: image samples (16-bit, two to a word) to packed 8-bit colours r | g << 8 | b << 16,
 *                    round(s * 255 / max) (grey replicated).
 *   grabcut_edges:   the 8-neighbour smoothness capacities, round(w scale) of the weights grabcut_smooth_sum left
 *                    (w = gamma_d exp(-beta |z_i - z_j|^2), pixel i's even edges d at weights[4 i + d / 2], an
 *                    odd edge the reverse of its neighbour's even one); 0 past the border (grid_graph.h's numbering).
 *   grabcut_terminals: the terminal capacities round(source scale) (first n words), round(sink scale) (next n)
 *                    from the data terms (doubles, source and sink interleaved).
 *   grabcut_seed_d2: k-means++ seeding of both sides at once: per side, 1 for its pixels (mode 0: a rank to draw
 *                    the first centre by), their squared distance to the first centre (1), or the least of that
 *                    and the distance to the newest centre (2); 0 for other pixels.
 *   grabcut_seed_find: the pixel i with scan[i] <= pick < scan[i + 1] per seeding side (the one whose running
 *                    sum of d2 first passes the pick), from the exclusive 64-bit scans of d2.
 * Labels are OpenCV's (0 background, 1 foreground, 2 probable background, 3 probable foreground) and 4,
 * unknown; side 1 is the foreground (labels 1 and 3), side 0 the background; unknown pixels have no side. */
#ifndef MV_GRABCUT_H
#define MV_GRABCUT_H
#include "grabcut_math.h"
#include "grid_graph.h"

MV_STRUCT_BEGIN(MvGrabCutParams)
  mv_u32 width;
  mv_u32 height;
  mv_u32 pixels;
  mv_u32 channels;   /* colours: samples per pixel, 1 or 3 */
  mv_u32 max_value;  /* colours: the samples' maximum */
  mv_u32 mode;       /* seed_d2: 0, 1 or 2 (above); data terms: 1 = components of labelled pixels' own side only */
  mv_u32 sum_at;     /* sums: the first 64-bit sum (two words, low first) this dispatch adds to */
  mv_u32 centres_bg; /* k-means: centres per side */
  mv_u32 centres_fg;
  mv_u32 seeding;    /* seeding: bit s set while side s draws centres */
  mv_u32 colour_bg;  /* seeding: each side's newest centre */
  mv_u32 colour_fg;
  mv_u32 pick_bg_lo; /* seeding: each side's drawn value, 64-bit */
  mv_u32 pick_bg_hi;
  mv_u32 pick_fg_lo;
  mv_u32 pick_fg_hi;
MV_STRUCT_END(MvGrabCutParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvGrabCutParams, 64);
MV_LAYOUT_AT(MvGrabCutParams, width, 0); MV_LAYOUT_AT(MvGrabCutParams, height, 4);
MV_LAYOUT_AT(MvGrabCutParams, pixels, 8); MV_LAYOUT_AT(MvGrabCutParams, channels, 12);
MV_LAYOUT_AT(MvGrabCutParams, max_value, 16); MV_LAYOUT_AT(MvGrabCutParams, mode, 20);
MV_LAYOUT_AT(MvGrabCutParams, sum_at, 24); MV_LAYOUT_AT(MvGrabCutParams, centres_bg, 28);
MV_LAYOUT_AT(MvGrabCutParams, centres_fg, 32); MV_LAYOUT_AT(MvGrabCutParams, seeding, 36);
MV_LAYOUT_AT(MvGrabCutParams, colour_bg, 40); MV_LAYOUT_AT(MvGrabCutParams, colour_fg, 44);
MV_LAYOUT_AT(MvGrabCutParams, pick_bg_lo, 48); MV_LAYOUT_AT(MvGrabCutParams, pick_bg_hi, 52);
MV_LAYOUT_AT(MvGrabCutParams, pick_fg_lo, 56); MV_LAYOUT_AT(MvGrabCutParams, pick_fg_hi, 60);
#endif

#define MV_GC_UNKNOWN 4u

/* The side of a label (1 foreground), 2 for unknown. */
MV_INLINE mv_u32 mv_gc_side(mv_u32 label) {
  return label == MV_GC_UNKNOWN ? 2u : ((label == 1u || label == 3u) ? 1u : 0u);
}

MV_INLINE mv_u32 mv_gc_dist2(mv_u32 a, mv_u32 b) {
  mv_u32 s = 0u;
  for (mv_u32 k = 0u; k < 3u; ++k) {
    mv_i32 d = MV_I32((a >> (8u * k)) & 255u) - MV_I32((b >> (8u * k)) & 255u);
    s += MV_U32(d * d);
  }
  return s;
}

MV_INLINE void mv_gc_colours(MvBufU32 samples, MvBufU32 colour, MvGrabCutParams p, mv_u32 i) {
  mv_u32 packed = 0u;
  mv_u32 top = MV_MAX(p.max_value, 1u);
  for (mv_u32 a = 0u; a < 3u; ++a) {
    mv_u32 s = i * p.channels + (p.channels == 3u ? a : 0u);
    mv_u32 v = MV_MIN((MV_LD(samples, s >> 1) >> (16u * (s & 1u))) & 65535u, top);
    packed |= ((v * 255u + top / 2u) / top) << (8u * a);
  }
  MV_ST(colour, i, packed);
}

/* gamma_d exp(-beta |z_i - z_j|^2) of pixel i's edge d, 0 past the border; the same from both ends, so each pair
 * is computed once (its even end) and kept for the capacities. */
MV_INLINE mv_f64 mv_gc_smooth(MvBufU32 colour, MvBufF64 c, MvGrabCutParams p, mv_u32 i, mv_u32 d) {
  mv_i32 nx = MV_I32(i % p.width) + mv_grid_dx(d);
  mv_i32 ny = MV_I32(i / p.width) + mv_grid_dy(d);
  if (nx < 0 || ny < 0 || nx >= MV_I32(p.width) || ny >= MV_I32(p.height)) return 0.0;
  mv_u32 d2 = mv_gc_dist2(MV_LD(colour, i), MV_LD(colour, MV_U32(ny) * p.width + MV_U32(nx)));
  MV_PRECISE mv_f64 x = MV_LD(c, MV_GC_BETA) * MV_F64(d2);
  MV_PRECISE mv_f64 w = MV_LD(c, d < 4u ? MV_GC_GAMMA : MV_GC_GAMMA_DIAG) * mv_gc_exp_neg(c, x);
  return w;
}

MV_INLINE void mv_gc_edges(MvBufF64 weights, MvBufF64 c, MvBufU32 edges, MvGrabCutParams p, mv_u32 i) {
  for (mv_u32 d = 0u; d < 8u; ++d) {
    mv_i32 nx = MV_I32(i % p.width) + mv_grid_dx(d);
    mv_i32 ny = MV_I32(i / p.width) + mv_grid_dy(d);
    mv_u32 q = 0u;
    if (nx >= 0 && ny >= 0 && nx < MV_I32(p.width) && ny < MV_I32(p.height)) {
      mv_u32 end = (d & 1u) == 0u ? i : MV_U32(ny) * p.width + MV_U32(nx);
      MV_PRECISE mv_f64 w = MV_LD(weights, 4u * end + (d >> 1)) * MV_LD(c, MV_GC_SCALE);
      q = MV_U32(mv_gc_round(w));
    }
    MV_ST(edges, i * 8u + d, q);
  }
}

MV_INLINE void mv_gc_terminals(MvBufF64 terms, MvBufF64 c, MvBufU32 q, MvGrabCutParams p, mv_u32 i) {
  MV_PRECISE mv_f64 s = MV_LD(terms, 2u * i) * MV_LD(c, MV_GC_SCALE);
  MV_PRECISE mv_f64 t = MV_LD(terms, 2u * i + 1u) * MV_LD(c, MV_GC_SCALE);
  MV_ST(q, i, MV_U32(mv_gc_round(s)));
  MV_ST(q, p.pixels + i, MV_U32(mv_gc_round(t)));
}

MV_INLINE mv_u32 mv_gc_seed_value(mv_u32 mode, mv_u32 old, mv_u32 colour, mv_u32 centre) {
  if (mode == 0u) return 1u;
  mv_u32 d = mv_gc_dist2(colour, centre);
  return mode == 1u ? d : MV_MIN(old, d);
}

MV_INLINE void mv_gc_seed_d2(MvBufU32 colour, MvBufU32 labels, MvBufU32 d2_bg, MvBufU32 d2_fg, MvGrabCutParams p,
                             mv_u32 i) {
  mv_u32 side = mv_gc_side(MV_LD(labels, i));
  mv_u32 z = MV_LD(colour, i);
  if ((p.seeding & 1u) != 0u)
    MV_ST(d2_bg, i, side == 0u ? mv_gc_seed_value(p.mode, MV_LD(d2_bg, i), z, p.colour_bg) : 0u);
  if ((p.seeding & 2u) != 0u)
    MV_ST(d2_fg, i, side == 1u ? mv_gc_seed_value(p.mode, MV_LD(d2_fg, i), z, p.colour_fg) : 0u);
}

MV_INLINE void mv_gc_seed_find(MvBufU64 scan_bg, MvBufU64 scan_fg, MvBufU32 found, MvGrabCutParams p, mv_u32 i) {
  mv_u64 pick_bg = MV_U64(p.pick_bg_lo) | (MV_U64(p.pick_bg_hi) << 32);
  mv_u64 pick_fg = MV_U64(p.pick_fg_lo) | (MV_U64(p.pick_fg_hi) << 32);
  if ((p.seeding & 1u) != 0u && MV_LD(scan_bg, i) <= pick_bg && pick_bg < MV_LD(scan_bg, i + 1u)) MV_ST(found, 0u, i);
  if ((p.seeding & 2u) != 0u && MV_LD(scan_fg, i) <= pick_fg && pick_fg < MV_LD(scan_fg, i + 1u)) MV_ST(found, 1u, i);
}

#endif /* MV_GRABCUT_H */

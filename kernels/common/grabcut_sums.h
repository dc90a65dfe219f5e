/* GrabCut's sums as integer reductions (so every device gets the same bits whatever the order of the adds): each
 * work-item sums its pixels' terms privately, then adds them into the group's shared array `acc` of 64-bit sums
 * (two 32-bit words each, low first, the carry out of the low word added to the high one), and the group adds
 * each non-zero sum into the sums buffer the same way with global 32-bit atomics, at channels p.sum_at + c. An entry declares MV_SHARED(mv_u32, acc, 2 * channels)
 * before including this header (GLSL resolves `acc` here). Grid-stride over pixels; the barriers are outside
 * the pixel loop, so every work-item of a group reaches them.
 *   grabcut_beta_sum (1 sum):  squared colour differences over the 8-neighbour pairs, each pair once.
 *   grabcut_smooth_sum (1):    the smoothness weights of every pixel's 8 edges, each round(w 2^20), each pair's
 *                              weight computed once and kept in weights for grabcut_edges (grabcut.h).
 *   grabcut_data (1):          the data terms (doubles, source and sink interleaved) with the lambda of hard
 *                              labels, less each pixel's common part, and their sum as round(t 2^20); each
 *                              pixel's likeliest component in either mixture (a hard label in its own; mode 1:
 *                              every labelled pixel in its own, no terms) into comp (bits 0-7 background,
 *                              8-15 foreground).
 *   grabcut_moments (100):     per side and component b = 5 side + k, at 10 b: count, sums of z_a, sums of
 *                              z_a z_b (00 01 02 11 12 22) over the labelled pixels: what a Gaussian fit needs.
 *   grabcut_kmeans (40):       each labelled pixel to its side's nearest k-means centre (the lowest among equals)
 *                              into comp, and per side and centre, at 4 (5 side + k): count and sums of z_a.
 *   grabcut_labels (1):        a cut's source side (one byte a pixel) to probable labels, hard labels kept;
 *                              the count of labels changed. */
#ifndef MV_GRABCUT_SUMS_H
#define MV_GRABCUT_SUMS_H
#include "grabcut.h"

MV_INLINE void mv_gc_acc_add(MV_SHARED_PARAM(mv_u32, acc) mv_u32 ch, mv_u64 v) {
  mv_u32 lo = MV_U32(v & MV_U64(0xffffffffu));
  mv_u32 hi = MV_U32(v >> 32);
  if (lo != 0u) {
    mv_u32 old = MV_SHARED_ATOMIC_ADD(acc, 2u * ch, lo);
    if (old + lo < old) hi += 1u;
  }
  if (hi != 0u) MV_SHARED_ATOMIC_ADD(acc, 2u * ch + 1u, hi);
}

MV_INLINE void mv_gc_acc_clear(MV_SHARED_PARAM(mv_u32, acc) mv_u32 channels) {
  for (mv_u32 w = MV_LOCAL_ID(); w < 2u * channels; w += MV_LOCAL_SIZE()) acc[w] = 0u;
  MV_BARRIER();
}

MV_INLINE void mv_gc_acc_flush(MV_SHARED_PARAM(mv_u32, acc) MvBufU32 sums, mv_u32 channels, mv_u32 at) {
  MV_BARRIER();
  for (mv_u32 ch = MV_LOCAL_ID(); ch < channels; ch += MV_LOCAL_SIZE()) {
    mv_u32 lo = acc[2u * ch];
    mv_u32 hi = acc[2u * ch + 1u];
    if (lo != 0u) {
      mv_u32 old = MV_ATOMIC_ADD(sums, 2u * (at + ch), lo);
      if (old + lo < old) hi += 1u;
    }
    if (hi != 0u) MV_ATOMIC_ADD(sums, 2u * (at + ch) + 1u, hi);
  }
}

MV_INLINE void mv_gc_beta_sum(MV_SHARED_PARAM(mv_u32, acc) MvBufU32 colour, MvBufU32 sums, MvGrabCutParams p) {
  mv_gc_acc_clear(MV_SHARED_ARG(acc) 1u);
  mv_u64 s = 0u;
  for (mv_u32 i = MV_GLOBAL_ID(); i < p.pixels; i += MV_GLOBAL_SIZE()) {
    for (mv_u32 d = 0u; d < 8u; d += 2u) {
      mv_i32 nx = MV_I32(i % p.width) + mv_grid_dx(d);
      mv_i32 ny = MV_I32(i / p.width) + mv_grid_dy(d);
      if (nx < 0 || ny < 0 || nx >= MV_I32(p.width) || ny >= MV_I32(p.height)) continue;
      s += MV_U64(mv_gc_dist2(MV_LD(colour, i), MV_LD(colour, MV_U32(ny) * p.width + MV_U32(nx))));
    }
  }
  mv_gc_acc_add(MV_SHARED_ARG(acc) 0u, s);
  mv_gc_acc_flush(MV_SHARED_ARG(acc) sums, 1u, p.sum_at);
}

MV_INLINE void mv_gc_smooth_sum(MV_SHARED_PARAM(mv_u32, acc) MvBufU32 colour, MvBufF64 c, MvBufF64 weights,
                                MvBufU32 sums, MvGrabCutParams p) {
  mv_gc_acc_clear(MV_SHARED_ARG(acc) 1u);
  mv_u64 s = 0u;
  for (mv_u32 i = MV_GLOBAL_ID(); i < p.pixels; i += MV_GLOBAL_SIZE()) {
    for (mv_u32 d = 0u; d < 8u; d += 2u) { /* the pair's other end (edge d ^ 1) has the same weight */
      mv_f64 w = mv_gc_smooth(colour, c, p, i, d);
      MV_ST(weights, 4u * i + (d >> 1), w);
      s += 2u * mv_gc_round(w * MV_GC_FIX);
    }
  }
  mv_gc_acc_add(MV_SHARED_ARG(acc) 0u, s);
  mv_gc_acc_flush(MV_SHARED_ARG(acc) sums, 1u, p.sum_at);
}

MV_INLINE void mv_gc_data(MV_SHARED_PARAM(mv_u32, acc) MvBufU32 colour, MvBufU32 labels, MvBufU32 comp,
                          MvBufF64 c, MvBufF64 terms, MvBufU32 sums, MvGrabCutParams p) {
  mv_gc_acc_clear(MV_SHARED_ARG(acc) 1u);
  mv_u64 total = 0u;
  for (mv_u32 i = MV_GLOBAL_ID(); i < p.pixels; i += MV_GLOBAL_SIZE()) {
    mv_u32 l = MV_LD(labels, i);
    mv_u32 side = mv_gc_side(l);
    mv_u32 z = MV_LD(colour, i);
    mv_u32 k = MV_LD(comp, i);
    MV_PRECISE mv_f64 s = 0.0;
    MV_PRECISE mv_f64 t = 0.0;
    if (p.mode == 1u || l == 0u || l == 1u) {
      if (side == 2u) continue;
      MvGcFit own = mv_gc_mixture(c, side, z);
      k = (k & ~(255u << (8u * side))) | (own.component << (8u * side));
      s = l == 1u ? MV_LD(c, MV_GC_LAMBDA) : 0.0;
      t = l == 0u ? MV_LD(c, MV_GC_LAMBDA) : 0.0;
    } else {
      MvGcFit b = mv_gc_mixture(c, 0u, z);
      MvGcFit f = mv_gc_mixture(c, 1u, z);
      k = b.component | (f.component << 8u);
      s = b.energy;
      t = f.energy;
    }
    MV_ST(comp, i, k);
    if (p.mode == 1u) continue;
    MV_PRECISE mv_f64 shared_part = MV_FMIN(s, t);
    MV_PRECISE mv_f64 source = s - shared_part;
    MV_PRECISE mv_f64 sink = t - shared_part;
    MV_ST(terms, 2u * i, source);
    MV_ST(terms, 2u * i + 1u, sink);
    total += mv_gc_round(source * MV_GC_FIX) + mv_gc_round(sink * MV_GC_FIX);
  }
  mv_gc_acc_add(MV_SHARED_ARG(acc) 0u, total);
  mv_gc_acc_flush(MV_SHARED_ARG(acc) sums, 1u, p.sum_at);
}

MV_INLINE void mv_gc_moments(MV_SHARED_PARAM(mv_u32, acc) MvBufU32 colour, MvBufU32 labels, MvBufU32 comp,
                             MvBufU32 sums, MvGrabCutParams p) {
  mv_gc_acc_clear(MV_SHARED_ARG(acc) 100u);
  mv_u64 m[100];
  for (mv_u32 ch = 0u; ch < 100u; ++ch) m[ch] = 0u;
  for (mv_u32 i = MV_GLOBAL_ID(); i < p.pixels; i += MV_GLOBAL_SIZE()) {
    mv_u32 side = mv_gc_side(MV_LD(labels, i));
    if (side == 2u) continue;
    mv_u32 at = 10u * (5u * side + ((MV_LD(comp, i) >> (8u * side)) & 255u));
    mv_u32 z = MV_LD(colour, i);
    mv_u32 r = z & 255u, g = (z >> 8) & 255u, b = (z >> 16) & 255u;
    m[at] += 1u;
    m[at + 1u] += MV_U64(r);
    m[at + 2u] += MV_U64(g);
    m[at + 3u] += MV_U64(b);
    m[at + 4u] += MV_U64(r * r);
    m[at + 5u] += MV_U64(r * g);
    m[at + 6u] += MV_U64(r * b);
    m[at + 7u] += MV_U64(g * g);
    m[at + 8u] += MV_U64(g * b);
    m[at + 9u] += MV_U64(b * b);
  }
  for (mv_u32 ch = 0u; ch < 100u; ++ch) mv_gc_acc_add(MV_SHARED_ARG(acc) ch, m[ch]);
  mv_gc_acc_flush(MV_SHARED_ARG(acc) sums, 100u, p.sum_at);
}

MV_INLINE void mv_gc_kmeans(MV_SHARED_PARAM(mv_u32, acc) MvBufU32 colour, MvBufU32 labels, MvBufU32 comp,
                            MvBufF64 c, MvBufU32 sums, MvGrabCutParams p) {
  mv_gc_acc_clear(MV_SHARED_ARG(acc) 40u);
  mv_u64 m[40];
  for (mv_u32 ch = 0u; ch < 40u; ++ch) m[ch] = 0u;
  for (mv_u32 i = MV_GLOBAL_ID(); i < p.pixels; i += MV_GLOBAL_SIZE()) {
    mv_u32 side = mv_gc_side(MV_LD(labels, i));
    if (side == 2u) continue;
    mv_u32 z = MV_LD(colour, i);
    mv_u32 centres = side == 0u ? p.centres_bg : p.centres_fg;
    mv_u32 best = 0u;
    MV_PRECISE mv_f64 bd = 0.0;
    for (mv_u32 k = 0u; k < centres; ++k) {
      mv_u32 at = MV_GC_CENTRES + (5u * side + k) * 3u;
      MV_PRECISE mv_f64 x = mv_gc_channel(z, 0u) - MV_LD(c, at);
      MV_PRECISE mv_f64 y = mv_gc_channel(z, 1u) - MV_LD(c, at + 1u);
      MV_PRECISE mv_f64 w = mv_gc_channel(z, 2u) - MV_LD(c, at + 2u);
      MV_PRECISE mv_f64 d = x * x + y * y + w * w;
      if (k == 0u || d < bd) {
        bd = d;
        best = k;
      }
    }
    mv_u32 k = MV_LD(comp, i);
    MV_ST(comp, i, (k & ~(255u << (8u * side))) | (best << (8u * side)));
    mv_u32 at = 4u * (5u * side + best);
    m[at] += 1u;
    m[at + 1u] += MV_U64(z & 255u);
    m[at + 2u] += MV_U64((z >> 8) & 255u);
    m[at + 3u] += MV_U64((z >> 16) & 255u);
  }
  for (mv_u32 ch = 0u; ch < 40u; ++ch) mv_gc_acc_add(MV_SHARED_ARG(acc) ch, m[ch]);
  mv_gc_acc_flush(MV_SHARED_ARG(acc) sums, 40u, p.sum_at);
}

MV_INLINE void mv_gc_labels(MV_SHARED_PARAM(mv_u32, acc) MvBufU32 source_side, MvBufU32 labels, MvBufU32 sums,
                            MvGrabCutParams p) {
  mv_gc_acc_clear(MV_SHARED_ARG(acc) 1u);
  mv_u64 changed = 0u;
  for (mv_u32 i = MV_GLOBAL_ID(); i < p.pixels; i += MV_GLOBAL_SIZE()) {
    mv_u32 l = MV_LD(labels, i);
    if (l == 0u || l == 1u) continue;
    mv_u32 n = ((MV_LD(source_side, i >> 2) >> (8u * (i & 3u))) & 255u) != 0u ? 3u : 2u;
    if (n == l) continue;
    MV_ST(labels, i, n);
    changed += 1u;
  }
  mv_gc_acc_add(MV_SHARED_ARG(acc) 0u, changed);
  mv_gc_acc_flush(MV_SHARED_ARG(acc) sums, 1u, p.sum_at);
}

#endif /* MV_GRABCUT_SUMS_H */

/* GrabCut's transcendental functions, the same bits on every device (docs/masks.md, "Exact GrabCut"): exp and
 * log as written here use only + - * and floor in double, in a fixed order, without contraction (mv_lang.h), so
 * no device's own exp or log (whose precision differs between OpenCL and Vulkan drivers) is ever called. Their
 * constants come from the host in the constants buffer (MvGrabCutConsts below), computed there once with the
 * host's correctly rounded arithmetic; accuracy is a few units in the last place of a double.
 *   exp(-x), x >= 0: x = (16 q + j) ln2/16 + r, so exp(-x) = 2^-q 2^(-j/16) exp(-r), r in [0, ln2/16), exp(-r) by
 *     its Taylor polynomial of degree 10 and 2^-q by squaring powers of two (exact); 0 past x = 707.
 *   log(t), t in [1, 5]: t = c (1 + u) with c = 1 + j/32, so log t = log c + log1p(u), u in [0, 1/32), log1p by its
 *     series to degree 12. */
#ifndef MV_GRABCUT_MATH_H
#define MV_GRABCUT_MATH_H
#include "floor64.h"

/* Double-precision constants, indices into the constants buffer (one buffer per GrabCut run). */
#define MV_GC_EXP2 0u      /* 16: 2^(-j/16) */
#define MV_GC_EXPC 16u     /* 11: (-1)^i / i!, i = 0..10 */
#define MV_GC_LOGA 27u     /* 12: (-1)^(i+1) / i, i = 1..12 */
#define MV_GC_K16 39u      /* 16 / ln 2 */
#define MV_GC_LN2HI 40u    /* ln2 / 16 in two parts (fdlibm's split): hi of 32 significant bits, so t hi is exact */
#define MV_GC_LN2LO 41u
#define MV_GC_BETA 42u     /* smoothness: beta, gamma (4-neighbours), gamma / sqrt 2 (diagonals) */
#define MV_GC_GAMMA 43u
#define MV_GC_GAMMA_DIAG 44u
#define MV_GC_SCALE 45u    /* capacity quantization scale */
#define MV_GC_LAMBDA 46u   /* hard labels' terminal weight */
#define MV_GC_UNDER 47u    /* -log 1e-300: a mixture density at or below 1e-300 counts as underflowed ... */
#define MV_GC_CLAMP 48u    /* ... and its -log as 690.8 */
#define MV_GC_ZERO 49u     /* -log of the smallest double: a component's density past it is 0 */
#define MV_GC_LOGC 64u     /* 129: log(1 + j/32) */
#define MV_GC_INVC 193u    /* 129: 1 / (1 + j/32) */
#define MV_GC_MIX 336u     /* 2 sides (0 background, 1 foreground) x 5 components x 16: mean[3], inverse[9] (row
                            * major), L = -log(weight / sqrt(det)), present (1 or 0), 2 unused */
#define MV_GC_CENTRES 496u /* k-means: 2 sides x 5 centres x 3 */
#define MV_GC_CONSTS 528u  /* doubles in all */
#define MV_GC_K 5u         /* mixture components */
#define MV_GC_FIX 1048576.0 /* 2^20: sums of capacities in fixed point */
#define MV_GC_GAP 40.0      /* mixtures: components this far (nats) above the best add no term */

/* Round half up of a non-negative double (llround's result for x >= 0), as an integer. */
MV_INLINE mv_u64 mv_gc_round(mv_f64 x) {
  MV_PRECISE mv_f64 f = mv_floor64(x);
  MV_PRECISE mv_f64 frac = x - f;
  return MV_U64(f) + (frac >= 0.5 ? 1u : 0u);
}

MV_INLINE mv_f64 mv_gc_exp_neg(MvBufF64 c, mv_f64 x) {
  if (!(x < 707.0)) return 0.0;
  MV_PRECISE mv_f64 t = mv_floor64(x * MV_LD(c, MV_GC_K16));
  mv_u32 k = MV_U32(t);
  MV_PRECISE mv_f64 r = (x - t * MV_LD(c, MV_GC_LN2HI)) - t * MV_LD(c, MV_GC_LN2LO);
  MV_PRECISE mv_f64 p = MV_LD(c, MV_GC_EXPC + 10u);
  for (mv_u32 i = 10u; i > 0u; --i) p = p * r + MV_LD(c, MV_GC_EXPC + i - 1u);
  p = p * MV_LD(c, MV_GC_EXP2 + (k & 15u));
  MV_PRECISE mv_f64 b = 0.5;
  for (mv_u32 q = k >> 4; q != 0u; q >>= 1) { /* 2^-q, exact: every factor a power of two above 2^-1022 */
    if ((q & 1u) != 0u) p = p * b;
    b = b * b;
  }
  return p;
}

MV_INLINE mv_f64 mv_gc_log_1_5(MvBufF64 c, mv_f64 t) {
  MV_PRECISE mv_f64 jf = mv_floor64((t - 1.0) * 32.0);
  mv_u32 j = MV_MIN(MV_U32(MV_FMAX(jf, 0.0)), 128u);
  MV_PRECISE mv_f64 u = (t - (1.0 + MV_F64(j) * 0.03125)) * MV_LD(c, MV_GC_INVC + j);
  MV_PRECISE mv_f64 p = MV_LD(c, MV_GC_LOGA + 11u);
  for (mv_u32 i = 11u; i > 0u; --i) p = p * u + MV_LD(c, MV_GC_LOGA + i - 1u);
  return MV_LD(c, MV_GC_LOGC + j) + u * p;
}

/* A packed colour (r | g << 8 | b << 16) channel. */
MV_INLINE mv_f64 mv_gc_channel(mv_u32 colour, mv_u32 a) { return MV_F64((colour >> (8u * a)) & 255u); }

/* -log of a mixture's density at a colour (side 0 background, 1 foreground), OpenCV's form without the
 * (2 pi)^-3/2 that cancels: e_k = m_k / 2 + L_k per component (m_k the Mahalanobis distance, in the order
 * sum over a, b of (d_a inv_ab) d_b), then min e - log(1 + sum over the others of exp(min e - e_k)), the sum
 * over the others less than MV_GC_GAP above min e only: exp(-40) < 5e-18 is below a double's resolution of
 * 1 + sum, and the test is a plain comparison of a difference, so every device skips the same terms.
 * component: the component of least e_k (the lowest among equals); 0 where every density underflows. */
MV_STRUCT_BEGIN(MvGcFit)
  mv_f64 energy;
  mv_u32 component;
MV_STRUCT_END(MvGcFit)

MV_INLINE MvGcFit mv_gc_mixture(MvBufF64 c, mv_u32 side, mv_u32 colour) {
  MvGcFit fit;
  fit.energy = MV_LD(c, MV_GC_CLAMP);
  fit.component = 0u;
  mv_f64 e[5];
  mv_u32 best = 5u;
  for (mv_u32 k = 0u; k < MV_GC_K; ++k) {
    mv_u32 at = MV_GC_MIX + (side * MV_GC_K + k) * 16u;
    e[k] = 0.0;
    if (MV_LD(c, at + 13u) == 0.0) continue;
    MV_PRECISE mv_f64 d0 = mv_gc_channel(colour, 0u) - MV_LD(c, at + 0u);
    MV_PRECISE mv_f64 d1 = mv_gc_channel(colour, 1u) - MV_LD(c, at + 1u);
    MV_PRECISE mv_f64 d2 = mv_gc_channel(colour, 2u) - MV_LD(c, at + 2u);
    MV_PRECISE mv_f64 m = 0.0;
    m = m + d0 * MV_LD(c, at + 3u) * d0;
    m = m + d0 * MV_LD(c, at + 4u) * d1;
    m = m + d0 * MV_LD(c, at + 5u) * d2;
    m = m + d1 * MV_LD(c, at + 6u) * d0;
    m = m + d1 * MV_LD(c, at + 7u) * d1;
    m = m + d1 * MV_LD(c, at + 8u) * d2;
    m = m + d2 * MV_LD(c, at + 9u) * d0;
    m = m + d2 * MV_LD(c, at + 10u) * d1;
    m = m + d2 * MV_LD(c, at + 11u) * d2;
    MV_PRECISE mv_f64 ek = 0.5 * m + MV_LD(c, at + 12u);
    e[k] = ek;
    if (best == 5u || ek < e[best]) best = k;
  }
  if (best == 5u || !(e[best] < MV_LD(c, MV_GC_ZERO))) return fit;
  fit.component = best;
  MV_PRECISE mv_f64 s = 0.0;
  for (mv_u32 k = 0u; k < MV_GC_K; ++k) {
    if (k == best || MV_LD(c, MV_GC_MIX + (side * MV_GC_K + k) * 16u + 13u) == 0.0) continue;
    MV_PRECISE mv_f64 gap = e[k] - e[best];
    if (gap < MV_GC_GAP) s = s + mv_gc_exp_neg(c, gap);
  }
  MV_PRECISE mv_f64 d = e[best] - mv_gc_log_1_5(c, 1.0 + s);
  if (d < MV_LD(c, MV_GC_UNDER)) fit.energy = d;
  return fit;
}

#endif /* MV_GRABCUT_MATH_H */

/* Probes of the kernel language layer (mv_lang.h): atomics on global and shared memory, barriers, work-group
 * ids, 2-D launches and arguments past the push constants. Tests run them on every device against what the
 * host expects (tests/test_lang.cpp); they are also the smallest examples of each feature.
 * Element type: 32-bit unless MV_LANG64 is defined before this header (one OpenCL program per width).
 * The bodies that use shared arrays are in lang_shared_atomics.h and lang_histogram.h: a .comp declares the
 * array before including one (GLSL resolves the name where the function is written). */
#ifndef MV_LANG_PROBE_H
#define MV_LANG_PROBE_H
#include "common/mv_lang.h"

MV_STRUCT_BEGIN(MvLangParams)
  mv_u32 n;      /* work items with a value */
  mv_u32 width;  /* 2-D probe: the grid */
  mv_u32 height;
  mv_u32 pad0;
MV_STRUCT_END(MvLangParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvLangParams, 16);
MV_LAYOUT_AT(MvLangParams, n, 0); MV_LAYOUT_AT(MvLangParams, width, 4); MV_LAYOUT_AT(MvLangParams, height, 8);
MV_LAYOUT_AT(MvLangParams, pad0, 12);
#endif

/* More argument bytes than Vulkan's 128 push-constant bytes (6 buffers + 96 bytes): a parameter buffer. */
#define MV_LANG_ARG_WORDS 23u
MV_STRUCT_BEGIN(MvLangArgsParams)
  mv_u32 slot;
  mv_u32 words[23];
MV_STRUCT_END(MvLangArgsParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvLangArgsParams, 96);
MV_LAYOUT_AT(MvLangArgsParams, slot, 0); MV_LAYOUT_AT(MvLangArgsParams, words, 4);
#endif

#define MV_LANG_SLOTS 6u  /* add count, min, max, or, exchange chain, compare-exchange sum */
#define MV_LANG_BINS 256u
#define MV_LANG_CELLS 8u

#if defined(MV_LANG64)
#define MvLangT mv_u64
#define MvLangBuf MvBufU64
#define MV_LANG_T(x) MV_U64(x)
#else
#define MvLangT mv_u32
#define MvLangBuf MvBufU32
#define MV_LANG_T(x) MV_U32(x)
#endif

/* Item i applies every atomic to `slots` (set up by the host: 0, ~0, 0, 0, a start value, 0); `olds` keeps
 * what the add and the exchange returned (each add result once: 0..n-1; the exchanges' results plus the final
 * value are the start value plus every item's value). The compare-exchange loop adds v to slot 5 and ends:
 * a failed exchange means another item's succeeded, so nobody waits for anybody (safe on PoCL). */
MV_INLINE void mv_lang_atomics(MvLangBuf vals, MvLangBuf slots, MvLangBuf olds, mv_u32 i) {
  MvLangT v = MV_LD(vals, i);
  MV_ST(olds, 2u * i, MV_ATOMIC_ADD(slots, 0u, MV_LANG_T(1)));
  MV_ATOMIC_MIN(slots, 1u, v);
  MV_ATOMIC_MAX(slots, 2u, v);
  MV_ATOMIC_OR(slots, 3u, v);
  MV_ST(olds, 2u * i + 1u, MV_ATOMIC_XCHG(slots, 4u, v));
  MvLangT expect = MV_LANG_T(0);
  for (;;) {
    MvLangT got = MV_ATOMIC_CAS(slots, 5u, expect, expect + v);
    if (got == expect) break;
    expect = got;
  }
}

#if !defined(MV_CPP) /* work-item ids exist on devices only */
/* 2-D launch: each cell of a width x height grid records its global, local and group ids. */
MV_INLINE void mv_lang_grid2d(MvBufU32 dst, mv_u32 width, mv_u32 height) {
  mv_u32 x = MV_GLOBAL_ID_D(0);
  mv_u32 y = MV_GLOBAL_ID_D(1);
  if (x < width && y < height) {
    mv_u32 cell = y * width + x;
    MV_ST(dst, 2u * cell, x | (y << 16));
    MV_ST(dst, 2u * cell + 1u,
          MV_LOCAL_ID_D(0) | (MV_LOCAL_ID_D(1) << 8) | (MV_GROUP_ID_D(0) << 16) | (MV_GROUP_ID_D(1) << 24));
  }
}
#endif

/* Every argument byte reaches the kernel: a checksum of five buffers' first words and all parameter words. */
MV_INLINE void mv_lang_args(MvBufU32 dst, MvBufU32 a, MvBufU32 b, MvBufU32 c, MvBufU32 d, MvBufU32 e,
                            MvLangArgsParams p) {
  mv_u32 sum = MV_LD(a, 0u) + 3u * MV_LD(b, 0u) + 5u * MV_LD(c, 0u) + 7u * MV_LD(d, 0u) + 11u * MV_LD(e, 0u);
  for (mv_u32 k = 0u; k < MV_LANG_ARG_WORDS; ++k) sum = sum * 31u + p.words[k];
  MV_ST(dst, p.slot, sum);
}

#endif /* MV_LANG_PROBE_H */

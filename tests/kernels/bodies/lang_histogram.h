/* Language-layer probe: a work-group histogram in a shared array `bins` (MV_LANG_BINS 32-bit counters).
 * A .comp declares MV_SHARED(mv_u32, bins, MV_LANG_BINS) before including this header. */
#ifndef MV_LANG_HISTOGRAM_H
#define MV_LANG_HISTOGRAM_H
#include "lang_probe.h"

/* A work-group histogram of the low byte of keys: shared bins cleared, filled by shared atomics over a
 * grid-stride loop, then added to the global histogram with global atomics. */
MV_INLINE void mv_lang_histogram(MV_SHARED_PARAM(mv_u32, bins) MvBufU32 keys, MvBufU32 hist, mv_u32 n) {
  mv_u32 lid = MV_LOCAL_ID();
  mv_u32 size = MV_LOCAL_SIZE();
  for (mv_u32 b = lid; b < MV_LANG_BINS; b += size) bins[b] = 0u;
  MV_BARRIER();
  for (mv_u32 i = MV_GLOBAL_ID(); i < n; i += MV_GLOBAL_SIZE()) MV_SHARED_ATOMIC_ADD(bins, MV_LD(keys, i) & 255u, 1u);
  MV_BARRIER();
  for (mv_u32 b = lid; b < MV_LANG_BINS; b += size)
    if (bins[b] != 0u) MV_ATOMIC_ADD(hist, b, bins[b]);
}

#endif /* MV_LANG_HISTOGRAM_H */

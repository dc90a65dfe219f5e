/* Language-layer probe: atomics on a work-group shared array `cells` (MV_LANG_CELLS elements of MvLangT).
 * A .comp declares MV_SHARED(MvLangT, cells, MV_LANG_CELLS) before including this header. */
#ifndef MV_LANG_SHARED_ATOMICS_H
#define MV_LANG_SHARED_ATOMICS_H
#include "lang_probe.h"

/* The same operations on one shared array per work-group (first item sets it up; barriers around), each
 * group's six results written to dst[6 * group ..]. Every item of the group calls it (uniform barriers). */
MV_INLINE void mv_lang_shared_atomics(MV_SHARED_PARAM(MvLangT, cells) MvLangBuf vals, MvLangBuf dst, mv_u32 n) {
  mv_u32 lid = MV_LOCAL_ID();
  mv_u32 i = MV_GLOBAL_ID();
  if (lid == 0u) {
    cells[0] = MV_LANG_T(0);
    cells[1] = ~MV_LANG_T(0);
    cells[2] = MV_LANG_T(0);
    cells[3] = MV_LANG_T(0);
    cells[4] = MV_LANG_T(0);
    cells[5] = MV_LANG_T(0);
  }
  MV_BARRIER();
  if (i < n) {
    MvLangT v = MV_LD(vals, i);
    MV_SHARED_ATOMIC_ADD(cells, 0u, MV_LANG_T(1));
    MV_SHARED_ATOMIC_MIN(cells, 1u, v);
    MV_SHARED_ATOMIC_MAX(cells, 2u, v);
    MV_SHARED_ATOMIC_OR(cells, 3u, v);
    MV_SHARED_ATOMIC_XCHG(cells, 4u, v);
    MvLangT expect = MV_LANG_T(0);
    for (;;) {
      MvLangT got = MV_SHARED_ATOMIC_CAS(cells, 5u, expect, expect + v);
      if (got == expect) break;
      expect = got;
    }
  }
  MV_BARRIER();
  if (lid < MV_LANG_SLOTS) MV_ST(dst, MV_LANG_SLOTS * MV_GROUP_ID() + lid, cells[lid]);
}

#endif /* MV_LANG_SHARED_ATOMICS_H */

/* Unique of sorted 64-bit keys, as flag -> exclusive scan -> compact (the scan is scan.h's):
 *   unique_flags: flags[i] = 1 where keys[i] starts a run of equal keys
 *   unique_compact: the first key of each run goes to dst[pos[i]]
 * Stream compaction in general is the same shape with other flags. */
#ifndef MV_UNIQUE_H
#define MV_UNIQUE_H
#include "mv_lang.h"

MV_STRUCT_BEGIN(MvUniqueParams)
  mv_u32 n;
  mv_u32 pad0;
MV_STRUCT_END(MvUniqueParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvUniqueParams, 8);
MV_LAYOUT_AT(MvUniqueParams, n, 0); MV_LAYOUT_AT(MvUniqueParams, pad0, 4);
#endif

MV_INLINE bool mv_run_starts(MvBufU64 keys, mv_u32 i) { return i == 0u || MV_LD(keys, i) != MV_LD(keys, i - 1u); }

MV_INLINE void mv_unique_flags(MvBufU64 keys, MvBufU32 flags, MvUniqueParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) MV_ST(flags, i, mv_run_starts(keys, i) ? 1u : 0u);
}

MV_INLINE void mv_unique_compact(MvBufU64 keys, MvBufU32 pos, MvBufU64 dst, MvUniqueParams p, mv_u32 gid,
                                 mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride)
    if (mv_run_starts(keys, i)) MV_ST(dst, MV_LD(pos, i), MV_LD(keys, i));
}

#endif

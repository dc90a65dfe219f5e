/* The page cache's update pass (Crassin's GigaVoxels cache: PhD thesis, Grenoble 2011, ch. 7.2-7.4), written once
 * for the host, OpenCL C and GLSL. The cache is `slots` device slots of one page each over `pages` page ids:
 *   usage[slot]  the last pass (stamp) that used the slot, written by whoever reads the slot's data;
 *   request[pg]  the last pass that asked for page pg, written on a miss (every writer writes the same stamp:
 *                no atomics, duplicates collapse, never cleared: older stamps are stale);
 *   table[pg]    the slot holding page pg, or MV_CACHE_NONE;
 *   owner[slot]  the page a slot holds, or MV_CACHE_NONE (the table's inverse, so eviction touches only the
 *                evicted pages' entries: one entry per page, no instancing);
 *   lru[]        every slot once, least recently used first;
 *   runs[pg]     for a resident page, its run: the most consecutive resident pages around it whose slots are
 *                consecutive too, so one offset moves the whole run's words into their slots and a traversal
 *                resolves the run once, not each page. One word (mv_cache_run_word): the pages of the run
 *                before pg and from pg on, each capped at 0xffff (a longer run is seen in parts). Stored in the
 *                table's buffer after the table and its tail (runs_at), written by cache_run_flags + scan +
 *                cache_run_bounds + cache_run_expand after the table changes.
 * After pass T: cache_lru_flags + scan + cache_lru_scatter partition lru stably into slots unused in T, then
 * slots used in T (one scan gives both sides); cache_request_flags + scan + cache_request_compact list the
 * pages requested in T that are not resident, in page order; the host caps that list to the unused slots and
 * the first `count` slots of lru become the victims: cache_evict invalidates what they held, the producer
 * fills a staging batch, cache_place copies it into the slots and cache_publish enters the pages that were
 * produced into the table (a failed page stays missing and its slot free) and stamps their slots with the
 * next pass. */
#ifndef MV_PAGE_CACHE_H
#define MV_PAGE_CACHE_H
#include "mv_lang.h"

#define MV_CACHE_NONE 0xffffffffu /* no slot / no page */
#define MV_CACHE_RUN_BEFORE(w) ((w) >> 16)   /* pages of the run before the page */
#define MV_CACHE_RUN_FROM(w) ((w) & 0xffffu) /* pages of the run from the page on (>= 1) */

/* The run word of page pg in the run [first, end). */
MV_INLINE mv_u32 mv_cache_run_word(mv_u32 first, mv_u32 end, mv_u32 pg) {
  return (MV_MIN(pg - first, 0xffffu) << 16) | MV_MIN(end - pg, 0xffffu);
}

MV_STRUCT_BEGIN(MvCacheParams)
  mv_u32 n;          /* items of this dispatch: slots, pages, victims, or staged words (cache_place) */
  mv_u32 stamp;      /* the pass just traced (T >= 1; 0 = never) */
  mv_u32 count;      /* victims: pages to load this update */
  mv_u32 page_words; /* 32-bit words per page */
  mv_u32 runs_at;    /* where runs[] starts in the table's buffer */
MV_STRUCT_END(MvCacheParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvCacheParams, 20);
MV_LAYOUT_AT(MvCacheParams, n, 0); MV_LAYOUT_AT(MvCacheParams, stamp, 4); MV_LAYOUT_AT(MvCacheParams, count, 8);
MV_LAYOUT_AT(MvCacheParams, page_words, 12); MV_LAYOUT_AT(MvCacheParams, runs_at, 16);
#endif

/* flags[i] = 1 when the slot at lru[i] was not used in pass `stamp` (it goes to the front). */
MV_INLINE void mv_cache_lru_flags(MvBufU32 usage, MvBufU32 lru, MvBufU32 flags, MvCacheParams p, mv_u32 gid,
                                  mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) MV_ST(flags, i, MV_LD(usage, MV_LD(lru, i)) != p.stamp ? 1u : 0u);
}

/* pos = exclusive scan of those flags (n + 1 values, pos[n] = unused slots): an unused slot goes to pos[i],
 * a used one to pos[n] + (i - pos[i]); both sides keep their order (a stable partition). */
MV_INLINE void mv_cache_lru_scatter(MvBufU32 lru, MvBufU32 pos, MvBufU32 next, MvCacheParams p, mv_u32 gid,
                                    mv_u32 stride) {
  mv_u32 unused = MV_LD(pos, p.n);
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 e = MV_LD(pos, i);
    mv_u32 to = MV_LD(pos, i + 1u) != e ? e : unused + (i - e);
    MV_ST(next, to, MV_LD(lru, i));
  }
}

/* flags[pg] = 1 when page pg was requested in pass `stamp` and is not resident. */
MV_INLINE void mv_cache_request_flags(MvBufU32 request, MvBufU32 table, MvBufU32 flags, MvCacheParams p,
                                      mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride)
    MV_ST(flags, i, MV_LD(request, i) == p.stamp && MV_LD(table, i) == MV_CACHE_NONE ? 1u : 0u);
}

/* The flagged page ids in order, from their scanned positions (the scatter writes the index itself). */
MV_INLINE void mv_cache_request_compact(MvBufU32 pos, MvBufU32 list, MvCacheParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 e = MV_LD(pos, i);
    if (MV_LD(pos, i + 1u) != e) MV_ST(list, e, i);
  }
}

/* Victim i (slot lru[i], i < n = count): its old page leaves the table and is reported in evicted[i]. */
MV_INLINE void mv_cache_evict(MvBufU32 lru, MvBufU32 table, MvBufU32 owner, MvBufU32 evicted, MvCacheParams p,
                              mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 slot = MV_LD(lru, i);
    mv_u32 old = MV_LD(owner, slot);
    if (old != MV_CACHE_NONE) MV_ST(table, old, MV_CACHE_NONE);
    MV_ST(owner, slot, MV_CACHE_NONE);
    MV_ST(evicted, i, old);
  }
}

/* Staged word w (n = count * page_words) of page w / page_words goes into its victim's slot when produced. */
MV_INLINE void mv_cache_place(MvBufU32 lru, MvBufU32 ok, MvBufU32 staging, MvBufU32 data, MvCacheParams p,
                              mv_u32 gid, mv_u32 stride) {
  for (mv_u32 w = gid; w < p.n; w += stride) {
    mv_u32 j = w / p.page_words;
    if (MV_LD(ok, j) != 0u) MV_ST(data, MV_LD(lru, j) * p.page_words + (w - j * p.page_words), MV_LD(staging, w));
  }
}

/* Page list[i] (i < n = count) enters the table at its victim's slot when it was produced, and the slot is
 * stamped with the next pass: a page loaded for the pass that asked for it counts as used by the next one, so
 * the next update moves it behind the pages nobody used instead of offering it as the first victim. */
MV_INLINE void mv_cache_publish(MvBufU32 lru, MvBufU32 list, MvBufU32 ok, MvBufU32 table, MvBufU32 owner,
                                MvBufU32 usage, MvCacheParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    if (MV_LD(ok, i) == 0u) continue;
    mv_u32 slot = MV_LD(lru, i);
    mv_u32 page = MV_LD(list, i);
    MV_ST(table, page, slot);
    MV_ST(owner, slot, page);
    MV_ST(usage, slot, p.stamp + 1u);
  }
}

/* Runs (n = pages): flags[pg] = 1 when resident page pg starts a run, i.e. page pg - 1 is missing or sits
 * elsewhere than the slot before pg's. */
MV_INLINE mv_u32 mv_cache_run_continues(MvBufU32 table, mv_u32 pg) {
  mv_u32 slot = MV_LD(table, pg);
  if (pg == 0u || slot == MV_CACHE_NONE || slot == 0u) return 0u;
  return MV_LD(table, pg - 1u) == slot - 1u ? 1u : 0u;
}
MV_INLINE void mv_cache_run_flags(MvBufU32 table, MvBufU32 flags, MvCacheParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride)
    MV_ST(flags, i, MV_LD(table, i) != MV_CACHE_NONE && mv_cache_run_continues(table, i) == 0u ? 1u : 0u);
}

/* pos = exclusive scan of those flags: resident page pg is in run pos[pg + 1] - 1, whose first page and end
 * go to bounds[2 run] and bounds[2 run + 1]. */
MV_INLINE void mv_cache_run_bounds(MvBufU32 table, MvBufU32 pos, MvBufU32 bounds, MvCacheParams p, mv_u32 gid,
                                   mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    if (MV_LD(table, i) == MV_CACHE_NONE) continue;
    mv_u32 run = MV_LD(pos, i + 1u) - 1u;
    if (MV_LD(pos, i) == run) MV_ST(bounds, 2u * run, i);
    if (i + 1u == p.n || mv_cache_run_continues(table, i + 1u) == 0u) MV_ST(bounds, 2u * run + 1u, i + 1u);
  }
}

/* runs[pg] (at table[runs_at] on) for every resident page; a missing page's is not read. */
MV_INLINE void mv_cache_run_expand(MvBufU32 table, MvBufU32 pos, MvBufU32 bounds, MvCacheParams p, mv_u32 gid,
                                   mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    if (MV_LD(table, i) == MV_CACHE_NONE) continue;
    mv_u32 run = MV_LD(pos, i + 1u) - 1u;
    MV_ST(table, p.runs_at + i, mv_cache_run_word(MV_LD(bounds, 2u * run), MV_LD(bounds, 2u * run + 1u), i));
  }
}

#endif /* MV_PAGE_CACHE_H */

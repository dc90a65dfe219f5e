/* Paged traversal's address layer (trace.h through the page cache, page_cache.h): resolving a stream word to
 * its cache slot, stamping the pages a ray reads, requesting the one it stopped at, and the step macros the
 * loop expands where it follows a pointer. Apart from the loop so that the walk reads as a walk; the macros
 * name the loop's locals and are meant for mv_trace alone. */
#ifndef MV_TRACE_PAGING_H
#define MV_TRACE_PAGING_H
#include "page_cache.h"
#include "trace_types.h"

/* Paged traversal: where stream word `addr` is in the cache's slots (data word slot << shift | offset), or
 * MV_CACHE_NONE when its page is not resident (the ray then stops there and requests the page once it has
 * left its loop: mv_page_request). A resident page's slot is stamped as used when the kernel stamps usage; a
 * stamp already there is not written again, so the rays sharing a page share its cache line. Each node lies
 * in one page, so a node's header and pointers resolve once, through the node's first word. */
MV_INLINE void mv_page_stamp(MvBufU32 usage, mv_u32 slot, mv_u32 stamp) {
  if (MV_LD(usage, slot) != stamp) MV_ST(usage, slot, stamp);
}
MV_INLINE mv_u32 mv_page_resolve(MvBufU32 table, MvBufU32 usage, MvTraceParams p, mv_u32 stamp_usage, mv_u64 addr) {
  const mv_u32 shift = MV_TRACE_PAGE_SHIFT(p);
  mv_u32 slot = MV_LD(table, MV_U32(addr >> shift));
  if (slot == MV_CACHE_NONE) return MV_CACHE_NONE;
  if (stamp_usage != 0u) mv_page_stamp(usage, slot, p.level_base[MV_TRACE_PAGE_STAMP]);
  return (slot << shift) | (MV_U32(addr) & ((1u << shift) - 1u));
}
#define MV_NO_WORD (~MV_U64(0u)) /* no stream word (left_run: none left the run) */
/* request[page] = stamp: every writer writes the same value, so duplicates collapse without atomics. */
MV_INLINE void mv_page_request(MvBufU32 request, MvTraceParams p, mv_u32 page) {
  const mv_u32 stamp = p.level_base[MV_TRACE_PAGE_STAMP];
  if (MV_LD(request, page) != stamp) MV_ST(request, page, stamp);
}

/* Paged traversal, in mv_trace: stream word `word` (a 64-bit virtual address) into `at`, its word in the slots
 * (32-bit: the cache is smaller than 16 GiB), and `coarse` set where its page is missing (`at` is then 0, so the
 * walk reads a harmless word by selects before it leaves). A word inside the run the ray resolved last
 * (consecutive resident pages in consecutive slots: page_cache.h; the run starts at virtual word run_lo, in the
 * slots at run_at) moves by its distance from run_lo: one subtract, one compare and one add, no table and no
 * dependent load on the way to the node. Any other goes through the table (MV_PAGE_ENTER), and its page's run
 * becomes the ray's:
 *  - where the cache stamps usage, at once; a page entered inside the run is stamped too, so the LRU sees every
 *    page read;
 *  - in a whole cache (no stamps: preloaded, one run), after the walk's loop (mv_trace): the step leaves the loop
 *    as a miss would, and the walk repeats it once the page is resolved. Lavapipe runs both arms of a branch for
 *    every lane, so the table's arm inside the loop cost it ~9 % of the trace where no ray ever took it. */
#define MV_PAGE_ENTER(word, at)                                                                                \
  /* a pointer past the pages (a damaged file) never resolves: its ray stays coarse and its query fails */     \
  at = ((word) >> page_shift) < MV_U64(page_count) ? mv_page_resolve(bricks, usage, p, stamp_usage, word)       \
                                                   : MV_CACHE_NONE;                                            \
  last_page = ((word) >> page_shift) < MV_U64(page_count) ? MV_U32((word) >> page_shift) : page_count - 1u;     \
  if (at != MV_CACHE_NONE) {                                                                                   \
    mv_u32 run_word = MV_LD(bricks, runs_at + last_page);                                                      \
    run_lo = MV_U64(last_page - MV_CACHE_RUN_BEFORE(run_word)) << page_shift;                                  \
    /* at least the page itself: a whole cache's walk repeats its step inside this run (mv_trace) */           \
    run_span = (MV_CACHE_RUN_BEFORE(run_word) + MV_MAX(MV_CACHE_RUN_FROM(run_word), 1u)) << page_shift;         \
    run_at = at - MV_U32((word) - run_lo);                                                                     \
  }

/* The whole cache's step (MV_PAGE_STEP). Leaving the run is rare (never in a cache preloaded in page order: one
 * run), and the two kinds of CPU device want it differently:
 *  - OpenCL (PoCL runs a work-item as scalar code): a branch that is never taken, out of the loop with the
 *    descent made (to the child's even cell: the undo after the loop takes it back), so the child's header load
 *    waits on one add after the pointer; the selects put a compare and a cmov on that chain of dependent loads,
 *    ~3 % of the trace;
 *  - GLSL (lavapipe runs every branch for all lanes): selects, and the walk leaves at the next step (limit). */
#if !defined(MV_GLSL)
#define MV_PAGE_STEP_WHOLE(word, at)                                                                           \
  if ((word) - run_lo >= MV_U64(run_span)) {                                                                   \
    left_run = (word);                                                                                         \
    coarse = 1u;                                                                                               \
    status = MV_TRACE_HIT;                                                                                     \
    nl -= 1u;                                                                                                  \
    lc -= 1u;                                                                                                  \
    s = s * 0.5f;                                                                                              \
    MV_UNROLL for (mv_u32 k = 0u; k < 3u; ++k) idx[k] = 2u * idx[k];                                           \
    break;                                                                                                     \
  }                                                                                                            \
  at = run_at + MV_U32((word) - run_lo);
#else
#define MV_PAGE_STEP_WHOLE(word, at)                                                                           \
  coarse = (word) - run_lo < MV_U64(run_span) ? 0u : 1u;                                                       \
  left_run = (word);                                                                                           \
  at = coarse != 0u ? 0u : run_at + MV_U32((word) - run_lo);
#endif

#define MV_PAGE_STEP(word, at)                                                                                 \
  if (stamp_usage == 0u) {                                                                                     \
    MV_PAGE_STEP_WHOLE(word, at)                                                                               \
  } else {                                                                                                     \
    if ((word) - run_lo < MV_U64(run_span)) {                                                                  \
      at = run_at + MV_U32((word) - run_lo);                                                                   \
      if (MV_U32((word) >> page_shift) != last_page) {                                                         \
        last_page = MV_U32((word) >> page_shift);                                                              \
        mv_page_stamp(usage, at >> page_shift, p.level_base[MV_TRACE_PAGE_STAMP]);                             \
      }                                                                                                        \
    } else {                                                                                                   \
      MV_PAGE_ENTER(word, at)                                                                                  \
    }                                                                                                          \
    coarse = at == MV_CACHE_NONE ? 1u : 0u;                                                                    \
    at = coarse != 0u ? 0u : at;                                                                               \
  }                                                                                                            \
  limit = coarse != 0u ? steps : limit; /* leave at the next step (mv_trace) */

#endif /* MV_TRACE_PAGING_H */

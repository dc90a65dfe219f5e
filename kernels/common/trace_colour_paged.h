/* A hit's colour entry through the page cache (trace_colour.h for the resident walk; trace_paging.h for the page
 * table): the same depth-first index, from a walk from the root down to the hit's cell, but every node read
 * through the page table and every earlier sibling's subtree size read from the cache's size plane at its
 * parent's pointer (host/formats/paging/paged_sizes.h), so the walk reads only the pages on the hit's own path:
 * those the trace just read. It runs after the trace's last pass, which left those pages resident; a page
 * missing all the same (a damaged file, a trace that gave up) gives MV_NO_ENTRY, never a wrong entry. */
#ifndef MV_TRACE_COLOUR_PAGED_H
#define MV_TRACE_COLOUR_PAGED_H
#include "trace_colour.h"
#include "trace_paging.h"

#define MV_NO_ENTRY 0xffffffffu

/* Stream word `word` in the cache's slots, or MV_CACHE_NONE (its page past the pages or not resident). */
MV_INLINE mv_u32 mv_paged_word_at(MvBufU32 table, mv_u32 page_count, mv_u32 shift, mv_u64 word) {
  if ((word >> shift) >= MV_U64(page_count)) return MV_CACHE_NONE;
  mv_u32 slot = MV_LD(table, MV_U32(word >> shift));
  return slot == MV_CACHE_NONE ? MV_CACHE_NONE : (slot << shift) | (MV_U32(word) & ((1u << shift) - 1u));
}

/* The depth-first entry of the full cell (x, y, z) of level lc. enc: MV_ENC_PAGED (a word stream; its levels'
 * starts after the page table, zeros for absolute pointers) or MV_ENC_PAGED_SSVDAG (inner nodes at 16-bit
 * words, bricks at 32-bit words 2b, 2b + 1; the plane holds a size per 16-bit word). */
MV_INLINE mv_u32 mv_paged_hit_entry(MvBufU32 slots, MvBufU32 table, MvBufU32 plane, MvTraceParams p, mv_u32 enc,
                                    mv_u32 x, mv_u32 y, mv_u32 z, mv_u32 lc) {
  const mv_u32 L = MV_TRACE_LEVELS(p);
  const mv_u32 shift = MV_TRACE_PAGE_SHIFT(p);
  const mv_u32 levels_at = p.level_base[MV_TRACE_PAGE_RUNS] - 2u * (L + 1u);
  const bool compact = enc == MV_ENC_PAGED_SSVDAG;
  /* the root: the start of its level (an ssvdag's in 16-bit words) */
  mv_u64 start = MV_LD_PAIR(table, levels_at + 2u * L);
  mv_u32 at = mv_paged_word_at(table, levels_at, shift, compact ? start >> 1 : start);
  if (at == MV_CACHE_NONE) return MV_NO_ENTRY;
  mv_u32 node = compact ? (at << 1) | MV_U32(start & MV_U64(1u)) : at; /* an ssvdag inner node: a 16-bit word */
  mv_u32 hdr = compact ? mv_inner_word(MV_LD_PAIR(slots, node >> 1), node) : MV_LD(slots, node);
  mv_u32 lo = 0u, hi = 0u; /* ssvdag: the brick, once the walk is in one */
  mv_u32 mir = 0u;
  mv_u32 index = 0u;
  for (mv_u32 l = L; l > lc; --l) {
    mv_u32 a = mv_colour_octant(x, y, z, l, lc); /* the octant as seen */
    bool in_brick = compact && l <= 2u;
    mv_u32 occ = mv_colour_occupancy(enc, l, hdr, lo, hi, node);
    mv_u32 skip = 1u;
    mv_u32 next = 0u, next_tag = 0u;
    for (mv_u32 b = 0u; b < 8u; ++b) {
      mv_u32 v = b ^ mir;
      if (b > a || ((occ >> v) & 1u) == 0u) continue;
      mv_u32 size = 1u, ptr = v, tag = 0u;
      mv_u32 t8 = mv_xmajor_octant(v);
      if (in_brick && l == 2u) {
        size = 1u + MV_POPCOUNT(mv_sub_block_occupancy(lo, hi, v));
      } else if (compact && l >= 3u) { /* the pointer's 16-bit words; its child's size at the first */
        mv_u32 q = mv_ssvdag_child_at(node, hdr, t8);
        mv_u32 w = mv_inner_words(MV_LD_PAIR(slots, q >> 1), q);
        ptr = mv_ssvdag_offset(w, mv_ssvdag_child_code(hdr, t8));
        tag = mv_ssvdag_tag(w);
        size = MV_LD(plane, q);
      } else if (!compact && l >= 2u) {
        mv_u32 q = mv_word_child_at(node, hdr, t8);
        ptr = MV_LD(slots, q);
        tag = mv_word_child_tag(hdr, t8);
        size = MV_LD(plane, q);
      }
      if (b < a) skip += size;
      else {
        next = ptr;
        next_tag = tag;
      }
    }
    index += skip;
    mir = mir ^ next_tag;
    node = next; /* in a brick: the sub-block's slot */
    if (l - 1u == lc || (compact && l <= 2u) || (!compact && l == 1u)) continue; /* the hit's cell, or no page */
    /* the child's page: resident, as the trace read it (a brick's two words lie in one page) */
    start = MV_LD_PAIR(table, levels_at + 2u * (l - 1u));
    mv_u64 word = compact && l == 3u ? start + MV_U64(2u) * MV_U64(next) : start + MV_U64(next);
    at = mv_paged_word_at(table, levels_at, shift, compact && l > 3u ? word >> 1 : word);
    if (at == MV_CACHE_NONE) return MV_NO_ENTRY;
    if (compact && l == 3u) {
      lo = MV_LD(slots, at);
      hi = MV_LD(slots, at + 1u);
    } else if (compact) {
      node = (at << 1) | MV_U32(word & MV_U64(1u));
      hdr = mv_inner_word(MV_LD_PAIR(slots, node >> 1), node);
    } else {
      node = at;
      hdr = MV_LD(slots, at);
    }
  }
  return index;
}

#if !defined(MV_CPP)
/* One work-item's share of hits [p.first, p.first + p.count): each hit's entry (mv_paged_hit_entry), MV_NO_ENTRY
 * for a miss. The host turns entries into colours (the colour section stays in the file). */
MV_INLINE void mv_paged_hit_entries(MvBufU32 hits, MvBufU32 slots, MvBufU32 table, MvBufU32 plane, MvBufU32 entries,
                                    MvTraceParams p, mv_u32 gid, mv_u32 gsize, mv_u32 enc) {
  for (mv_u32 j = gid; j < p.count; j += gsize) {
    mv_u32 i = p.first + j;
    MvHit h = mv_load_hit(hits, i);
    mv_u32 e = MV_NO_ENTRY;
    if (MV_INFO_STATUS(h.info) == MV_TRACE_HIT) e = mv_paged_hit_entry(slots, table, plane, p, enc, h.x, h.y, h.z, MV_INFO_LEVEL(h.info));
    MV_ST(entries, i, e);
  }
}
#endif

#endif /* MV_TRACE_COLOUR_PAGED_H */

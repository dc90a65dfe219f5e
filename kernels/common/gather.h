/* Gather of fixed-size records by index: dst record i = src record index[i]. The columns of a point cloud
 * (coordinates, colours, normals, intensities, extra bytes) into another order in one pass each. Host side:
 * host/core/primitives/gather.cpp.
 * A record is `units` units of 1, 2 or 4 bytes (the widest that divides its size). Records of whole words go a
 * work-item per record; records of 2-byte units a work-item per output word; records of an odd size a work-item
 * per 4 records (whole words). A word may hold units of two records, but no two work-items share a word, so
 * records of any size pack without atomics and the bytes are the same on every device. */
#ifndef MV_GATHER_H
#define MV_GATHER_H
#include "mv_lang.h"

MV_STRUCT_BEGIN(MvGatherParams)
  mv_u32 words;       /* output words of this dispatch */
  mv_u32 units;       /* output units of this dispatch (records times units per record) */
  mv_u32 per_record;  /* units per record */
  mv_u32 unit_shift;  /* log2 of a unit's bytes: 0, 1 or 2 */
  mv_u32 lo;          /* the source holds records [lo, lo + count) of the whole source: a slice of a source */
  mv_u32 count;       /* larger than one binding; records outside it are left to the passes of other slices */
  mv_u32 merge;       /* 0: the first pass, which writes whole words; 1: later passes keep the units not theirs */
  mv_u32 block;       /* 0: grid-stride (GPUs); else a block of this many records (words) a work-item (CPUs) */
MV_STRUCT_END(MvGatherParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvGatherParams, 32);
MV_LAYOUT_AT(MvGatherParams, words, 0); MV_LAYOUT_AT(MvGatherParams, units, 4);
MV_LAYOUT_AT(MvGatherParams, per_record, 8); MV_LAYOUT_AT(MvGatherParams, unit_shift, 12);
MV_LAYOUT_AT(MvGatherParams, lo, 16); MV_LAYOUT_AT(MvGatherParams, count, 20);
MV_LAYOUT_AT(MvGatherParams, merge, 24); MV_LAYOUT_AT(MvGatherParams, block, 28);
#endif

#define MV_GATHER_AHEAD 32u /* records (words) a CPU's block prefetches ahead */

MV_INLINE void mv_gather_records(MvBufConstU32 src, MvBufConstU32 index, MvBufU32 dst, MvGatherParams p, mv_u32 gid,
                                 mv_u32 stride) {
  if (p.unit_shift == 2u) {
    /* Records of whole words: a work-item per record, whose words no other record shares. */
    mv_u32 records = p.units / p.per_record;
    MvItems items = mv_items(p.block, gid, stride, records);
    mv_u32 r = items.begin, end = items.end, step = items.step;
    for (; r < end; r += step) {
      /* A CPU runs a block one record at a time: ask for a record a few dozen ahead while this one is copied. */
      if (p.block != 0u && r + MV_GATHER_AHEAD < end)
        MV_PREFETCH(src, MV_U64(MV_LD(index, r + MV_GATHER_AHEAD) - p.lo) * MV_U64(p.per_record));
      mv_u32 rec = MV_LD(index, r) - p.lo; /* wraps past count below lo */
      if (rec >= p.count) continue;
      mv_u64 s = MV_U64(rec) * MV_U64(p.per_record);
      mv_u32 d = r * p.per_record;
      mv_u32 u = 0u;
      for (; u + 1u < p.per_record; u += 2u) {  /* two words a load: lavapipe pays per load instruction */
        mv_u64 v = MV_LD_PAIR(src, s + MV_U64(u));
        MV_ST(dst, d + u, MV_U32(v & MV_U64(0xffffffffu)));
        MV_ST(dst, d + u + 1u, MV_U32(v >> 32u));
      }
      if (u < p.per_record) MV_ST(dst, d + u, MV_LD_FAR(src, s + MV_U64(u)));
    }
    return;
  }
  if (p.unit_shift == 1u) {
    /* Records of 2-byte units: a work-item per word, its two units straight-line (one division). */
    MvItems items = mv_items(p.block, gid, stride, p.words);
    mv_u32 w = items.begin, end = items.end, step = items.step;
    for (; w < end; w += step) {
      mv_u32 a = 2u * w;
      if (p.block != 0u && w + MV_GATHER_AHEAD < end) {
        mv_u32 ahead = 2u * (w + MV_GATHER_AHEAD) / p.per_record;
        MV_PREFETCH(src, (MV_U64(MV_LD(index, ahead) - p.lo) * MV_U64(p.per_record)) >> 1u);
      }
      mv_u32 r = a / p.per_record;
      mv_u32 u = a - r * p.per_record;
      mv_u32 word = p.merge != 0u ? MV_LD(dst, w) : 0u;
      mv_u32 rec = MV_LD(index, r) - p.lo;
      if (rec < p.count) {
        mv_u64 s = MV_U64(rec) * MV_U64(p.per_record) + MV_U64(u);
        word = (word & 0xffff0000u) | ((MV_LD_FAR(src, s >> 1u) >> (MV_U32(s & MV_U64(1u)) * 16u)) & 0xffffu);
      }
      if (a + 1u < p.units) {
        if (++u == p.per_record) {
          u = 0u;
          rec = MV_LD(index, r + 1u) - p.lo;
        }
        if (rec < p.count) {
          mv_u64 s = MV_U64(rec) * MV_U64(p.per_record) + MV_U64(u);
          word = (word & 0xffffu) | (((MV_LD_FAR(src, s >> 1u) >> (MV_U32(s & MV_U64(1u)) * 16u)) & 0xffffu) << 16u);
        }
      }
      MV_ST(dst, w, word);
    }
    return;
  }
  /* Records of bytes: a work-item per group of 4 records, which ends on a whole word: one index load per record,
   * the group's words written whole. */
  mv_u32 per_word = 4u >> p.unit_shift;
  mv_u32 unit_bits = 8u << p.unit_shift;
  mv_u32 mask = (1u << unit_bits) - 1u;
  mv_u32 group_words = p.per_record; /* (per_word records) x per_record units / per_word units a word */
  mv_u32 groups = (p.words + group_words - 1u) / group_words;
  for (mv_u32 t = gid; t < groups; t += stride) {
    mv_u32 r = t * per_word; /* the group's first record; its units then step along */
    mv_u32 u = 0u;
    mv_u32 g = t * group_words * per_word;
    mv_u32 rec = r < p.units / p.per_record ? MV_LD(index, r) - p.lo : 0u;
    for (mv_u32 j = 0u; j < group_words; ++j) {
      mv_u32 w = t * group_words + j;
      if (w >= p.words) break;
      mv_u32 word = p.merge != 0u ? MV_LD(dst, w) : 0u;
      for (mv_u32 k = 0u; k < per_word && g < p.units; ++k) {
        if (rec < p.count) { /* wraps past count below lo: left to another slice's pass */
          mv_u64 s = MV_U64(rec) * MV_U64(p.per_record) + MV_U64(u);
          mv_u32 at = MV_U32(s & MV_U64(per_word - 1u)) * unit_bits;
          mv_u32 v = (MV_LD_FAR(src, s >> (2u - p.unit_shift)) >> at) & mask;
          mv_u32 place = k * unit_bits;
          word = (word & ~(mask << place)) | (v << place);
        }
        ++g;
        if (++u == p.per_record) {
          u = 0u;
          ++r;
          if (g < p.units) rec = MV_LD(index, r) - p.lo;
        }
      }
      MV_ST(dst, w, word);
    }
  }
}

#endif

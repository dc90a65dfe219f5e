/* The symmetry-aware DAG's vocabulary (ssvdag.h): reflections of masks, stabilizers as tag normalization
 * tables, tag rows, the layout of the mask table, emitted entries (id, tag) and a node's orientation word. Every
 * level's reduction speaks it. */
#ifndef MV_SSVDAG_TAGS_H
#define MV_SSVDAG_TAGS_H
#include "dag.h"

MV_INLINE mv_u32 mv_reflect_mask(mv_u32 m, mv_u32 t) {
  /* bit c moves to c ^ t: swap neighbouring bits (x), pairs (y), nibbles (z) */
  if ((t & 1u) != 0u) m = ((m & 0x55u) << 1) | ((m >> 1) & 0x55u);
  if ((t & 2u) != 0u) m = ((m & 0x33u) << 2) | ((m >> 2) & 0x33u);
  if ((t & 4u) != 0u) m = ((m & 0x0fu) << 4) | ((m >> 4) & 0x0fu);
  return m;
}

/* A stabilizer as a tag normalization table: 3 bits per tag k, norm(k) = min over s in stab of k ^ s. */
#define MV_NORM_IDENTITY 0xFAC688u /* the table of the trivial stabilizer {0}: norm(k) = k */

MV_INLINE mv_u32 mv_norm_table(mv_u32 stab) {
  if (stab == 1u) return MV_NORM_IDENTITY;
  mv_u32 table = 0u;
  for (mv_u32 k = 0u; k < 8u; ++k) {
    mv_u32 best = k;
    for (mv_u32 s = 1u; s < 8u; ++s)
      if (((stab >> s) & 1u) != 0u) best = MV_MIN(best, k ^ s);
    table |= best << (3u * k);
  }
  return table;
}

MV_INLINE mv_u32 mv_norm_tag(mv_u32 t, mv_u32 table) { return (table >> (3u * t)) & 7u; }

/* The row of a pointer tagged t to a node with this tag table: field k = norm(t ^ k). */
MV_INLINE mv_u32 mv_tag_row(mv_u32 table, mv_u32 t) { return mv_xor_fields(table, t); }

/* Field k of a row: the tag seen through reflection k (field 0: the tag itself, normalized). */
MV_INLINE mv_u32 mv_row_field(mv_u32 row, mv_u32 k) { return (row >> (3u * k)) & 7u; }

/* The mask table (mv_leaf_table), MV_MASK_TABLE_WORDS words: per 8-bit mask m an info word (canonical mask, its
 * T* and its stabilizer) and the row of its tag; per reflection set s its tag table. */
#define MV_MASK_TABLE_WORDS 768u
MV_INLINE mv_u32 mv_mask_info_at(mv_u32 m) { return 2u * m; }
MV_INLINE mv_u32 mv_mask_row_at(mv_u32 m) { return 2u * m + 1u; }
MV_INLINE mv_u32 mv_tag_table_at(mv_u32 s) { return 512u + s; }

MV_INLINE mv_u32 mv_mask_info(mv_u32 canonical, mv_u32 tstar, mv_u32 stab) {
  return canonical | (tstar << 8) | (stab << 16);
}
MV_INLINE mv_u32 mv_mask_canonical(mv_u32 info) { return info & 0xffu; }
MV_INLINE mv_u32 mv_mask_tstar(mv_u32 info) { return (info >> 8) & 7u; }
MV_INLINE mv_u32 mv_mask_stabilizer(mv_u32 info) { return (info >> 16) & 0xffu; }

/* An entry of an emitted level (mv_dag_emit, mv_brick_emit): a child's id and tag (empty octants: 0); the
 * canonical keys hash children the same way. */
MV_INLINE mv_u64 mv_entry(mv_u32 id, mv_u32 tag) { return (MV_U64(id) << 3) | MV_U64(tag); }
MV_INLINE mv_u32 mv_entry_id(mv_u64 e) { return MV_U32(e >> 3); }
MV_INLINE mv_u32 mv_entry_tag(mv_u64 e) { return MV_U32(e) & 7u; }

/* A node's orientation in one word: its tag as its parent will see it (T* normalized by its stabilizer s) as
 * a row in bits 0..23, T* itself in bits 24..26; mtab (leaf_table) holds the tag table of every stabilizer. */
MV_INLINE mv_u32 mv_orientation(MvBufU32 mtab, mv_u32 t, mv_u32 s) {
  return mv_tag_row(MV_LD(mtab, mv_tag_table_at(s)), t) | (t << 24);
}

MV_INLINE mv_u32 mv_row_tstar(mv_u32 row) { return (row >> 24) & 7u; }

#endif /* MV_SSVDAG_TAGS_H */

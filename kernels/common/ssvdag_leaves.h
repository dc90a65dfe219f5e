/* The symmetry-aware DAG's level 1 (ssvdag.h): 2x2x2 nodes are classed by their canonical mask through one
 * 256-entry table, with no hashing and nothing written per node. */
#ifndef MV_SSVDAG_LEAVES_H
#define MV_SSVDAG_LEAVES_H
#include "ssvdag_tags.h"

/* Level 1 needs no hashing: a 2x2x2 node's class is its canonical mask (the mask itself without symmetry),
 * one of at most 256. leaf_table describes every mask once: word 2m = canonical mask | T* << 8 | stabilizer
 * << 16, word 2m + 1 = the row of its tag (T* normalized by the stabilizer), and word 512 + s = the tag table of
 * the reflection set s (meaningful for the subgroups: stabilizers). leaf_present marks the classes
 * that occur; their exclusive scan ranks them (ids in class order); leaf_classes gives each id its stored
 * mask. Nothing is written per node: level 2 reads its children's masks. */
MV_INLINE void mv_leaf_table(MvBufU32 table, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 m = gid; m < 256u; m += stride) {
    mv_u32 best = 0u, s = 1u, lowest = m;
    for (mv_u32 t = 1u; t < 8u; ++t) {
      mv_u32 r = mv_reflect_mask(m, t);
      if (r < lowest) {
        lowest = r;
        best = t;
      }
      if (r == m) s |= 1u << t;
    }
    MV_ST(table, mv_mask_info_at(m), mv_mask_info(lowest, best, s));
    MV_ST(table, mv_mask_row_at(m), mv_tag_row(mv_norm_table(s), best));
    MV_ST(table, mv_tag_table_at(m), mv_norm_table(m));
  }
}

MV_INLINE mv_u32 mv_leaf_class(MvBufU32 mask, MvBufU32 table, MvDagParams p, mv_u32 i) {
  return p.leaf == 2u ? mv_mask_canonical(MV_LD(table, mv_mask_info_at(MV_LD(mask, i)))) : MV_LD(mask, i);
}

MV_INLINE void mv_leaf_present(MvBufU32 mask, MvBufU32 table, MvBufU32 present, MvDagParams p, mv_u32 gid,
                               mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 c = mv_leaf_class(mask, table, p, i);
    if (MV_LD(present, c) == 0u) MV_ST(present, c, 1u); /* read first: few classes, millions of nodes */
  }
}

/* rank: the exclusive scan of the 256 presence flags (257 entries): class c occurs iff rank[c + 1] > rank[c]. */
MV_INLINE void mv_leaf_classes(MvBufU32 rank, MvBufU32 class_mask, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 c = gid; c < 256u; c += stride)
    if (MV_LD(rank, c + 1u) != MV_LD(rank, c)) MV_ST(class_mask, MV_LD(rank, c), c);
}

#endif /* MV_SSVDAG_LEAVES_H */

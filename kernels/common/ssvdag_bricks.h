/* The symmetry-aware DAG's level 2 (ssvdag.h): 4x4x4 bricks as exact 64-bit keys, their reflections, the
 * canonical brick of each class of equal bricks, and the emitted level. No hash and no verification: the key
 * is the brick. */
#ifndef MV_SSVDAG_BRICKS_H
#define MV_SSVDAG_BRICKS_H
#include "ssvdag_tags.h"

/* Level 2 needs no hash either: a node is a 4x4x4 brick, 64 bits (bit 8c + c' = octant c, then octant c' of
 * that child), its children's 2x2x2 masks as they lie (cmask: one per child slot, level 1's own masks). The
 * brick is an exact key: the sort groups equal bricks and no verification pass is needed. Level 1's ids and
 * tags are needed only where the DAG is written out (mv_brick_emit). */
MV_INLINE mv_u64 mv_brick(MvBufU32 mask, MvBufU32 first, MvBufU32 cmask, mv_u32 i) {
  mv_u32 m = MV_LD(mask, i), j = MV_LD(first, i);
  mv_u64 b = MV_U64(0);
  for (mv_u32 c = 0u; c < 8u; ++c) {
    if (((m >> c) & 1u) == 0u) continue;
    b |= MV_U64(MV_LD(cmask, j)) << (8u * c);
    j += 1u;
  }
  return b;
}

MV_INLINE void mv_brick_keys(MvBufU32 mask, MvBufU32 first, MvBufU32 cmask, MvBufU64 keys, MvBufU32 order,
                             MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    MV_ST(keys, i, mv_brick(mask, first, cmask, i));
    MV_ST(order, i, i);
  }
}

MV_INLINE mv_u64 mv_brick_swap(mv_u64 b, mv_u64 m, mv_u32 shift) {
  return ((b & m) << shift) | ((b >> shift) & m);
}

MV_INLINE mv_u64 mv_reflect_brick(mv_u64 b, mv_u32 t) {
  if ((t & 1u) != 0u) { /* x: index bits 0 and 3 */
    b = mv_brick_swap(b, MV_U64(0x5555555555555555UL), 1u);
    b = mv_brick_swap(b, MV_U64(0x00ff00ff00ff00ffUL), 8u);
  }
  if ((t & 2u) != 0u) { /* y: index bits 1 and 4 */
    b = mv_brick_swap(b, MV_U64(0x3333333333333333UL), 2u);
    b = mv_brick_swap(b, MV_U64(0x0000ffff0000ffffUL), 16u);
  }
  if ((t & 4u) != 0u) { /* z: index bits 2 and 5 */
    b = mv_brick_swap(b, MV_U64(0x0f0f0f0f0f0f0f0fUL), 4u);
    b = mv_brick_swap(b, MV_U64(0x00000000ffffffffUL), 32u);
  }
  return b;
}

/* With symmetry, for each class k of equal bricks (its representative node rep[k]; p.n = classes): the key
 * is the brick reflected by T*, the reflection whose (node mask, brick) is smallest (a reflection T flips
 * the same axis bit in c and c'; ties to the smaller T; only reflections giving the smallest mask are tried,
 * from mtab), and stab the reflections that leave the brick unchanged: exact like the stabilizer method, by
 * another total order of keys. Writes the key and the orientation (row: T* and tag row) per class. */
MV_INLINE void mv_brick_canon(MvBufU32 mask, MvBufU32 mtab, MvBufU32 first, MvBufU32 cmask, MvBufU32 rep,
                              MvBufU64 keys, MvBufU32 row, MvBufU32 order, MvDagParams p,
                              mv_u32 gid, mv_u32 stride) {
  for (mv_u32 k = gid; k < p.n; k += stride) {
    mv_u32 i = MV_LD(rep, k), info = MV_LD(mtab, mv_mask_info_at(MV_LD(mask, i)));
    mv_u32 t0 = mv_mask_tstar(info), ms = mv_mask_stabilizer(info), best = t0, s = 1u;
    mv_u64 base = mv_reflect_brick(mv_brick(mask, first, cmask, i), t0), lowest = base;
    for (mv_u32 g = 1u; g < 8u; ++g) { /* the other reflections with the smallest mask: t0 ^ g, g in ms */
      if (((ms >> g) & 1u) == 0u) continue;
      mv_u64 r = mv_reflect_brick(base, g);
      if (r < lowest || (r == lowest && (t0 ^ g) < best)) {
        lowest = r;
        best = t0 ^ g;
      }
      if (r == base) s |= 1u << g; /* g fixes the reflected brick, hence the brick */
    }
    MV_ST(row, k, mv_orientation(mtab, best, s));
    MV_ST(keys, k, lowest);
    MV_ST(order, k, k);
  }
}

/* Each node takes the id and orientation (row) of its class of equal bricks (id: in, then out: the class's id up to
 * reflection, cls). */
MV_INLINE void mv_brick_orient(MvBufU32 id, MvBufU32 cls, MvBufU32 crow, MvBufU32 row, MvDagParams p, mv_u32 gid,
                               mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 k = MV_LD(id, i);
    MV_ST(id, i, MV_LD(cls, k));
    MV_ST(row, i, MV_LD(crow, k));
  }
}

/* dag_emit for level 2: a child's (id, tag) come from its 2x2x2 mask (cmask, per child slot): its class is
 * its canonical mask (the mask itself without symmetry: p.seed_lo = 0), ranked by crank (leaf_present's
 * scan), its tag row from mtab (leaf_table). */
MV_INLINE void mv_brick_emit(MvBufU32 mask, MvBufU32 first, MvBufU32 cmask, MvBufU32 mtab, MvBufU32 crank,
                             MvBufU32 row, MvBufU32 rep, MvBufU32 out_mask, MvBufU64 out_entry, MvDagParams p,
                             mv_u32 gid, mv_u32 stride) {
  for (mv_u32 r = gid; r < p.n; r += stride) {
    mv_u32 node = MV_LD(rep, r);
    mv_u32 t = p.seed_lo != 0u ? mv_row_tstar(MV_LD(row, node)) : 0u;
    mv_u32 m = MV_LD(mask, node), j = MV_LD(first, node);
    MV_ST(out_mask, r, mv_reflect_mask(m, t));
    for (mv_u32 c = 0u; c < 8u; ++c) {
      mv_u64 e = MV_U64(0);
      if (((m >> c) & 1u) != 0u) {
        mv_u32 cm = MV_LD(cmask, j);
        if (p.seed_lo != 0u)
          e = mv_entry(MV_LD(crank, mv_mask_canonical(MV_LD(mtab, mv_mask_info_at(cm)))),
                       mv_norm_tag(t, MV_LD(mtab, mv_mask_row_at(cm))));
        else
          e = mv_entry(MV_LD(crank, cm), 0u);
        j += 1u;
      }
      MV_ST(out_entry, 8u * r + (c ^ t), e);
    }
  }
}

#endif /* MV_SSVDAG_BRICKS_H */

/* Symmetry-aware DAG reduction (SSVDAG): subtrees equal up to the 8 reflections about the axis-aligned
 * planes through a node's centre share one representative; pointers carry a 3-bit reflection tag.
 *
 * The exact stabilizer method (notes on Jaspe Villanueva 2018, 1.6(c)). A reflection T is a 3-bit mask
 * (bit 0 = x, 1 = y, 2 = z) and, with Morton octants, maps octant c to c ^ T. Every representative keeps
 * stab = the set of reflections that leave it unchanged (an 8-bit set); a tag t on a pointer to it is
 * normalized to min over s in stab of t ^ s, so equal subtrees always get equal (id, tag) pairs. For node n
 * and each T, the reflected node n_T has child[c ^ T] = child[c] with tag norm(tag[c] ^ T). n's class is
 * keyed by Key(n_T*) with T* = argmin_T Key(n_T) (lexicographic: mask, then (id, tag) by octant), stab(n) =
 * {S : Key(n_S) == Key(n_0)}, and the parent's pointer to n becomes (class, norm(T*)). Level-1 nodes (2x2x2
 * masks) are keyed by the mask alone. Exact: two subtrees get the same key iff one is a reflection of the
 * other, so no symmetry is missed. The hash / sort / runs / verify pipeline of dag.h then assigns ids. */
#ifndef MV_SSVDAG_H
#define MV_SSVDAG_H
#include "dag.h"

MV_INLINE mv_u32 mv_reflect_mask(mv_u32 m, mv_u32 t) {
  mv_u32 r = 0u;
  for (mv_u32 c = 0u; c < 8u; ++c)
    if (((m >> c) & 1u) != 0u) r |= 1u << (c ^ t);
  return r;
}

MV_INLINE mv_u32 mv_norm_tag(mv_u32 t, mv_u32 stab) {
  mv_u32 best = t;
  for (mv_u32 s = 1u; s < 8u; ++s)
    if (((stab >> s) & 1u) != 0u) best = MV_MIN(best, t ^ s);
  return best;
}

/* Entry o (octant) of n_T, as one comparable number: (child id << 3) | normalized tag; 0 if empty. */
MV_INLINE mv_u64 mv_reflected_entry(MvBufU32 mask, MvBufU32 first, MvBufU32 cid, MvBufU32 ctag, MvBufU32 cstab,
                                    mv_u32 i, mv_u32 t, mv_u32 o) {
  mv_u32 m = MV_LD(mask, i);
  mv_u32 c = o ^ t;
  if (((m >> c) & 1u) == 0u) return MV_U64(0);
  mv_u32 j = MV_LD(first, i) + mv_popcount8(m & ((1u << c) - 1u));
  mv_u32 id = MV_LD(cid, j);
  mv_u32 tag = mv_norm_tag(MV_LD(ctag, j) ^ t, MV_LD(cstab, id));
  return (MV_U64(id) << 3) | MV_U64(tag);
}

/* T* (smallest key, ties to the smaller T) and stab of each node, comparing the reflected keys entry by
 * entry from the children's (id, tag, stab) read once. */
MV_INLINE void mv_ssvdag_canon(MvBufU32 mask, MvBufU32 first, MvBufU32 cid, MvBufU32 ctag, MvBufU32 cstab,
                               MvBufU32 tstar, MvBufU32 stab, MvBufU64 canon, MvDagParams p, mv_u32 gid,
                               mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 m = MV_LD(mask, i);
    if (p.leaf != 0u) { /* a 2x2x2 node: its reflected masks are the whole key */
      mv_u32 best = 0u, s = 1u, lowest = m;
      for (mv_u32 t = 1u; t < 8u; ++t) {
        mv_u32 r = mv_reflect_mask(m, t);
        if (r < lowest) {
          lowest = r;
          best = t;
        }
        if (r == m) s |= 1u << t;
      }
      MV_ST(tstar, i, best);
      MV_ST(stab, i, s);
      continue;
    }
    mv_u32 id[8], tag[8], cs[8];
    mv_u32 j = p.leaf == 0u ? MV_LD(first, i) : 0u;
    for (mv_u32 c = 0u; c < 8u; ++c) {
      id[c] = 0u;
      tag[c] = 0u;
      cs[c] = 1u;
      if (p.leaf == 0u && ((m >> c) & 1u) != 0u) {
        id[c] = MV_LD(cid, j);
        tag[c] = MV_LD(ctag, j);
        cs[c] = MV_LD(cstab, id[c]);
        j += 1u;
      }
    }
    /* Compare the reflected keys entry by entry, computing entries from the children as needed. */
    mv_u32 best = 0u;
    mv_u32 s = 1u;
    for (mv_u32 t = 1u; t < 8u; ++t) {
      mv_i32 vs_best = 0, vs_id = 0;
      mv_u32 mt = mv_reflect_mask(m, t), mb = mv_reflect_mask(m, best);
      if (mt != mb) vs_best = mt < mb ? -1 : 1;
      if (mt != m) vs_id = mt < m ? -1 : 1;
      for (mv_u32 o = 0u; o < 8u && (vs_best == 0 || vs_id == 0); ++o) {
        mv_u32 c = o ^ t, cb = o ^ best;
        mv_u64 x = ((m >> c) & 1u) != 0u ? (MV_U64(id[c]) << 3) | MV_U64(mv_norm_tag(tag[c] ^ t, cs[c])) : MV_U64(0);
        mv_u64 xb = ((m >> cb) & 1u) != 0u ? (MV_U64(id[cb]) << 3) | MV_U64(mv_norm_tag(tag[cb] ^ best, cs[cb]))
                                             : MV_U64(0);
        mv_u64 x0 = ((m >> o) & 1u) != 0u ? (MV_U64(id[o]) << 3) | MV_U64(mv_norm_tag(tag[o], cs[o])) : MV_U64(0);
        if (vs_best == 0 && x != xb) vs_best = x < xb ? -1 : 1;
        if (vs_id == 0 && x != x0) vs_id = x < x0 ? -1 : 1;
      }
      if (vs_best < 0) best = t;
      if (vs_id == 0) s |= 1u << t;
    }
    MV_ST(tstar, i, best);
    MV_ST(stab, i, s);
    /* the canonical key, for hashing and verification: mask, then the entries of n_T* */
    MV_ST(canon, 9u * i, MV_U64(mv_reflect_mask(m, best)));
    for (mv_u32 o = 0u; o < 8u; ++o) {
      mv_u32 c = o ^ best;
      MV_ST(canon, 9u * i + 1u + o,
            ((m >> c) & 1u) != 0u ? (MV_U64(id[c]) << 3) | MV_U64(mv_norm_tag(tag[c] ^ best, cs[c])) : MV_U64(0));
    }
  }
}

/* Hash of node i's canonical key (written by ssvdag_canon). */
MV_INLINE void mv_ssvdag_hash(MvBufU64 canon, MvBufU64 hashes, MvBufU32 order, MvDagParams p, mv_u32 gid,
                              mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u64 h = (MV_U64(p.seed_hi) << 32) | MV_U64(p.seed_lo);
    for (mv_u32 k = 0u; k < 9u; ++k) h = mv_hash_mix(h, MV_LD(canon, 9u * i + k));
    MV_ST(hashes, i, h);
    MV_ST(order, i, i);
  }
}

/* Canonical keys of node i and its run's representative equal? A mismatch is a hash collision. */
MV_INLINE void mv_ssvdag_verify(MvBufU64 canon, MvBufU32 id, MvBufU32 rep, MvBufU32 collided, MvDagParams p,
                                mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 r = MV_LD(rep, MV_LD(id, i));
    bool same = true;
    for (mv_u32 k = 0u; k < 9u; ++k) same = same && MV_LD(canon, 9u * i + k) == MV_LD(canon, 9u * r + k);
    if (!same) MV_ST(collided, 0u, 1u);
  }
}

/* Each node's tag as its parent will see it, and each class's stab (from its representative). */
MV_INLINE void mv_ssvdag_tags(MvBufU32 tstar, MvBufU32 stab, MvBufU32 id, MvBufU32 rep, MvBufU32 tag,
                              MvBufU32 idstab, MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 s = MV_LD(stab, i);
    MV_ST(tag, i, mv_norm_tag(MV_LD(tstar, i), s));
    mv_u32 k = MV_LD(id, i);
    if (MV_LD(rep, k) == i) MV_ST(idstab, k, s);
  }
}

/* The reduced level in id order, for the host: class r's stored mask (its representative reflected by T*)
 * and its 8 entries ((child id << 3) | tag, 0 = empty) in octant order. p.seed_lo = 1 with symmetry; without
 * it tstar, ctag and cstab are null and tags are 0. */
MV_INLINE void mv_dag_emit(MvBufU32 mask, MvBufU32 first, MvBufU32 cid, MvBufU32 ctag, MvBufU32 cstab, MvBufU32 tstar,
                           MvBufU32 rep, MvBufU32 out_mask, MvBufU64 out_entry, MvDagParams p, mv_u32 gid,
                           mv_u32 stride) {
  for (mv_u32 r = gid; r < p.n; r += stride) {
    mv_u32 node = MV_LD(rep, r);
    mv_u32 t = p.seed_lo != 0u ? MV_LD(tstar, node) : 0u; /* seed_lo: 1 = symmetric */
    MV_ST(out_mask, r, mv_reflect_mask(MV_LD(mask, node), t));
    if (p.leaf != 0u) continue;
    mv_u32 m = MV_LD(mask, node);
    for (mv_u32 o = 0u; o < 8u; ++o) {
      mv_u64 e = MV_U64(0);
      if (p.seed_lo != 0u) e = mv_reflected_entry(mask, first, cid, ctag, cstab, node, t, o);
      else if (((m >> o) & 1u) != 0u) e = MV_U64(MV_LD(cid, MV_LD(first, node) + mv_popcount8(m & ((1u << o) - 1u)))) << 3;
      MV_ST(out_entry, 8u * r + o, e);
    }
  }
}

/* Level 1 needs no hashing: a 2x2x2 node's class is its canonical mask (the mask itself without symmetry),
 * one of at most 256. leaf_present marks the masks that occur; their exclusive scan ranks them; leaf_ids
 * gives each node the rank of its mask as id (ids in mask order) and each id a representative (any member:
 * all give the same stored mask and stabilizer). tstar is null without symmetry. */
MV_INLINE mv_u32 mv_leaf_class(MvBufU32 mask, MvBufU32 tstar, MvDagParams p, mv_u32 i) {
  return p.leaf == 2u ? mv_reflect_mask(MV_LD(mask, i), MV_LD(tstar, i)) : MV_LD(mask, i);
}

MV_INLINE void mv_leaf_present(MvBufU32 mask, MvBufU32 tstar, MvBufU32 present, MvDagParams p, mv_u32 gid,
                               mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) MV_ST(present, mv_leaf_class(mask, tstar, p, i), 1u);
}

MV_INLINE void mv_leaf_ids(MvBufU32 mask, MvBufU32 tstar, MvBufU32 rank, MvBufU32 id, MvBufU32 rep, MvDagParams p,
                           mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 r = MV_LD(rank, mv_leaf_class(mask, tstar, p, i));
    MV_ST(id, i, r);
    MV_ST(rep, r, i);
  }
}

#endif

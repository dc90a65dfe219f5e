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
 * masks) are keyed by the mask alone (a 256-entry table), level-2 nodes by their 4x4x4 brick (64 exact bits,
 * ordered by (mask, brick): another total order, as exact). Exact: two subtrees get the same key iff one is a
 * reflection of the other, so no symmetry is missed. The hash / sort / runs / verify pipeline of dag.h then
 * assigns ids (bricks need no hash and no verification). */
#ifndef MV_SSVDAG_H
#define MV_SSVDAG_H
#include "dag.h"

MV_INLINE mv_u32 mv_reflect_mask(mv_u32 m, mv_u32 t) {
  /* bit c moves to c ^ t: swap neighbouring bits (x), pairs (y), nibbles (z) */
  if ((t & 1u) != 0u) m = ((m & 0x55u) << 1) | ((m >> 1) & 0x55u);
  if ((t & 2u) != 0u) m = ((m & 0x33u) << 2) | ((m >> 2) & 0x33u);
  if ((t & 4u) != 0u) m = ((m & 0x0fu) << 4) | ((m >> 4) & 0x0fu);
  return m;
}

/* A class's stabilizer as a tag normalization table: 3 bits per tag k, norm(k) = min over s in stab of k ^ s.
 * Pointers look their tag up instead of searching the stabilizer (kernels keep the table per class). */
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

/* Node i's orientation: T*, its stabilizer, and its tag as its parent will see it (T* normalized). */
MV_INLINE void mv_store_orientation(MvBufU32 tstar, MvBufU32 tag, MvBufU32 stab, mv_u32 i, mv_u32 t, mv_u32 s) {
  mv_u32 best = t;
  for (mv_u32 g = 1u; g < 8u && s != 1u; ++g)
    if (((s >> g) & 1u) != 0u) best = MV_MIN(best, t ^ g);
  MV_ST(tstar, i, t);
  MV_ST(tag, i, best);
  MV_ST(stab, i, s);
}

/* T* (smallest key, ties to the smaller T) and stab of each node above level 2, comparing the reflected keys
 * entry by entry from the children's (id, tag, tag table) read once (mtab: leaf_table, which describes every
 * 8-bit mask), and the hash of the canonical key Key(n_T*) (seeded by p.seed_lo) for the sort that groups
 * equal keys. */
MV_INLINE void mv_ssvdag_canon(MvBufU32 mask, MvBufU32 mtab, MvBufU32 first, MvBufU32 cid, MvBufU32 ctag,
                               MvBufU32 cnorm, MvBufU32 tstar, MvBufU32 tag_out, MvBufU32 stab, MvBufU64 hashes,
                               MvBufU32 order, MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 m = MV_LD(mask, i);
    mv_u32 id[8], tag[8], cs[8];
    mv_u32 tg0[8]; /* the unreflected key's normalized tags (its entries: (id, tg0) by octant) */
    mv_u32 j = MV_LD(first, i);
    for (mv_u32 c = 0u; c < 8u; ++c) {
      id[c] = 0u;
      tag[c] = 0u;
      cs[c] = MV_NORM_IDENTITY;
      tg0[c] = 0u;
      if (((m >> c) & 1u) != 0u) {
        id[c] = MV_LD(cid, j);
        tag[c] = MV_LD(ctag, j);
        cs[c] = MV_LD(cnorm, id[c]);
        tg0[c] = mv_norm_tag(tag[c], cs[c]);
        j += 1u;
      }
    }
    /* Only reflections that give the smallest mask can be T*, only those that fix the mask can fix the node:
     * the mask table gives the mask's own T* (t0) and stabilizer (ms); asymmetric masks need no entries. */
    mv_u32 info = MV_LD(mtab, 2u * m);
    mv_u32 mb = info & 0xffu, t0 = (info >> 8) & 7u, ms = (info >> 16) & 0xffu;
    mv_u32 best = t0, s = 1u;
    for (mv_u32 g = 1u; g < 8u; ++g) {
      if (((ms >> g) & 1u) == 0u) continue;
      mv_u32 t = t0 ^ g;
      mv_i32 vs = 0; /* Key(n_t) against Key(n_best), entry (id, tag) by entry: same mask, same octants present */
      for (mv_u32 o = 0u; o < 8u && vs == 0; ++o) {
        mv_u32 c = o ^ t, cb = o ^ best;
        if (((m >> c) & 1u) == 0u) continue;
        if (id[c] != id[cb]) {
          vs = id[c] < id[cb] ? -1 : 1;
        } else {
          mv_u32 x = mv_norm_tag(tag[c] ^ t, cs[c]), xb = mv_norm_tag(tag[cb] ^ best, cs[cb]);
          if (x != xb) vs = x < xb ? -1 : 1;
        }
      }
      if (vs < 0 || (vs == 0 && t < best)) best = t;
      bool same = true; /* Key(n_g) against Key(n_0) */
      for (mv_u32 o = 0u; o < 8u && same; ++o) {
        mv_u32 c = o ^ g;
        if (((m >> c) & 1u) != 0u) same = id[c] == id[o] && mv_norm_tag(tag[c] ^ g, cs[c]) == tg0[o];
      }
      if (same) s |= 1u << g;
    }
    mv_store_orientation(tstar, tag_out, stab, i, best, s);
    /* hash of the canonical key: mask, then the entries of n_T* in its present octants */
    mv_u64 h = (MV_U64(p.seed_hi) << 32) | MV_U64(p.seed_lo);
    h = mv_hash_mix(h, MV_U64(mb));
    for (mv_u32 o = 0u; o < 8u; ++o) {
      mv_u32 c = o ^ best;
      if (((m >> c) & 1u) != 0u)
        h = mv_hash_mix(h, (MV_U64(id[c]) << 3) | MV_U64(mv_norm_tag(tag[c] ^ best, cs[c])));
    }
    MV_ST(hashes, i, h);
    MV_ST(order, i, i);
  }
}

/* Level 2 needs no hash either: a node is a 4x4x4 brick, 64 bits (bit 8c + c' = octant c, then octant c' of
 * that child), rebuilt from its children's class masks (cmask: level 1's stored masks; with symmetry a child
 * (id, tag) is its class mask reflected by tag). The brick is an exact key: the sort groups equal bricks and
 * no verification pass is needed. With symmetry the key is the brick reflected by T*, the reflection whose
 * (node mask, brick) is smallest (a reflection T flips the same axis bit in c and c'; ties to the smaller T;
 * only reflections giving the smallest mask are tried, from mtab), and stab the reflections that leave the
 * brick unchanged: exact like the stabilizer method, by another total order of keys. p.leaf = 2: symmetric
 * (tstar, tag, stab written). */
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

MV_INLINE void mv_brick_keys(MvBufU32 mask, MvBufU32 mtab, MvBufU32 first, MvBufU32 cid, MvBufU32 ctag,
                             MvBufU32 cmask, MvBufU32 tstar, MvBufU32 tag, MvBufU32 stab, MvBufU64 keys,
                             MvBufU32 order, MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 m = MV_LD(mask, i), j = MV_LD(first, i);
    mv_u64 b = MV_U64(0);
    for (mv_u32 c = 0u; c < 8u; ++c) {
      if (((m >> c) & 1u) == 0u) continue;
      mv_u32 child = MV_LD(cmask, 8u * MV_LD(cid, j) + (p.leaf == 2u ? MV_LD(ctag, j) : 0u));
      b |= MV_U64(child) << (8u * c);
      j += 1u;
    }
    if (p.leaf == 2u) { /* order: the reflected node mask first, then the brick; see mv_ssvdag_canon */
      mv_u32 info = MV_LD(mtab, 2u * m);
      mv_u32 t0 = (info >> 8) & 7u, ms = (info >> 16) & 0xffu, best = t0, s = 1u;
      mv_u64 base = mv_reflect_brick(b, t0), lowest = base;
      for (mv_u32 g = 1u; g < 8u; ++g) { /* the other reflections with the smallest mask: t0 ^ g, g in ms */
        if (((ms >> g) & 1u) == 0u) continue;
        mv_u64 r = mv_reflect_brick(base, g);
        if (r < lowest || (r == lowest && (t0 ^ g) < best)) {
          lowest = r;
          best = t0 ^ g;
        }
        if (r == base) s |= 1u << g; /* g fixes the reflected brick, hence the brick */
      }
      mv_store_orientation(tstar, tag, stab, i, best, s);
      b = lowest;
    }
    MV_ST(keys, i, b);
    MV_ST(order, i, i);
  }
}

/* Canonical keys of node i and its run's representative equal? A mismatch is a hash collision. The keys
 * are rebuilt from the children and each node's T* (cheaper than storing nine words per node). */
MV_INLINE void mv_ssvdag_verify(MvBufU32 mask, MvBufU32 first, MvBufU32 cid, MvBufU32 ctag, MvBufU32 cnorm,
                                MvBufU32 tstar, MvBufU32 id, MvBufU32 rep, MvBufU32 collided, MvDagParams p,
                                mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 r = MV_LD(rep, MV_LD(id, i));
    if (r == i) continue;
    mv_u32 ti = MV_LD(tstar, i), tr = MV_LD(tstar, r);
    mv_u32 m = MV_LD(mask, i), mr = MV_LD(mask, r), j = MV_LD(first, i);
    bool same = mv_reflect_mask(m, ti) == mv_reflect_mask(mr, tr);
    for (mv_u32 c = 0u; c < 8u && same; ++c) { /* i's child c against the rep's child at the same octant */
      if (((m >> c) & 1u) == 0u) continue;
      mv_u32 id = MV_LD(cid, j);
      mv_u32 cr = c ^ ti ^ tr, jr = MV_LD(first, r) + mv_popcount8(mr & ((1u << cr) - 1u));
      mv_u32 idr = MV_LD(cid, jr);
      same = id == idr && mv_norm_tag(MV_LD(ctag, j) ^ ti, MV_LD(cnorm, id)) ==
                              mv_norm_tag(MV_LD(ctag, jr) ^ tr, MV_LD(cnorm, idr));
      j += 1u;
    }
    if (!same) MV_ST(collided, 0u, 1u);
  }
}

/* Each class's tag table, from its representative's stabilizer (p.n = classes). */
MV_INLINE void mv_class_norms(MvBufU32 rep, MvBufU32 stab, MvBufU32 idnorm, MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 k = gid; k < p.n; k += stride) MV_ST(idnorm, k, mv_norm_table(MV_LD(stab, MV_LD(rep, k))));
}

/* The reduced level in id order, for the host: class r's stored mask (its representative reflected by T*)
 * and its 8 entries ((child id << 3) | tag, 0 = empty) in octant order. p.seed_lo = 1 with symmetry; without
 * it tstar, ctag and cnorm are null and tags are 0. */
MV_INLINE void mv_dag_emit(MvBufU32 mask, MvBufU32 first, MvBufU32 cid, MvBufU32 ctag, MvBufU32 cnorm, MvBufU32 tstar,
                           MvBufU32 rep, MvBufU32 out_mask, MvBufU64 out_entry, MvDagParams p, mv_u32 gid,
                           mv_u32 stride) {
  for (mv_u32 r = gid; r < p.n; r += stride) {
    mv_u32 node = MV_LD(rep, r);
    mv_u32 t = p.seed_lo != 0u ? MV_LD(tstar, node) : 0u; /* seed_lo: 1 = symmetric */
    MV_ST(out_mask, r, mv_reflect_mask(MV_LD(mask, node), t));
    if (p.leaf != 0u) continue;
    mv_u32 m = MV_LD(mask, node), j = MV_LD(first, node);
    for (mv_u32 c = 0u; c < 8u; ++c) { /* child c lands at octant c ^ t; each child read once */
      mv_u64 e = MV_U64(0);
      if (((m >> c) & 1u) != 0u) {
        mv_u32 id = MV_LD(cid, j);
        e = MV_U64(id) << 3;
        if (p.seed_lo != 0u) e |= MV_U64(mv_norm_tag(MV_LD(ctag, j) ^ t, MV_LD(cnorm, id)));
        j += 1u;
      }
      MV_ST(out_entry, 8u * r + (c ^ t), e);
    }
  }
}

/* Level 1 needs no hashing: a 2x2x2 node's class is its canonical mask (the mask itself without symmetry),
 * one of at most 256. leaf_table describes every mask once: word 2m = canonical mask | T* << 8 | tag << 11
 * (the tag normalized by the mask's stabilizer) | stabilizer << 16, word 2m + 1 = its tag normalization
 * table. leaf_present marks the classes that occur; their exclusive scan ranks them (ids in class order);
 * leaf_classes gives each id its stored mask (word 8 id, then its 7 reflections, for level 2's bricks) and,
 * with symmetry (p.leaf == 2), its tag table; leaf_ids gives each node its id and, with symmetry, its tag.
 * Nothing is written per node to shared addresses but the presence flags. */
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
    mv_u32 norm = mv_norm_table(s);
    MV_ST(table, 2u * m, lowest | (best << 8) | (mv_norm_tag(best, norm) << 11) | (s << 16));
    MV_ST(table, 2u * m + 1u, norm);
  }
}

MV_INLINE mv_u32 mv_leaf_class(MvBufU32 mask, MvBufU32 table, MvDagParams p, mv_u32 i) {
  return p.leaf == 2u ? MV_LD(table, 2u * MV_LD(mask, i)) & 0xffu : MV_LD(mask, i);
}

MV_INLINE void mv_leaf_present(MvBufU32 mask, MvBufU32 table, MvBufU32 present, MvDagParams p, mv_u32 gid,
                               mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 c = mv_leaf_class(mask, table, p, i);
    if (MV_LD(present, c) == 0u) MV_ST(present, c, 1u); /* read first: few classes, millions of nodes */
  }
}

/* rank: the exclusive scan of the 256 presence flags (257 entries): class c occurs iff rank[c + 1] > rank[c]. */
MV_INLINE void mv_leaf_classes(MvBufU32 table, MvBufU32 rank, MvBufU32 class_mask, MvBufU32 idnorm, MvDagParams p,
                               mv_u32 gid, mv_u32 stride) {
  for (mv_u32 c = gid; c < 256u; c += stride) {
    mv_u32 r = MV_LD(rank, c);
    if (MV_LD(rank, c + 1u) == r) continue;
    for (mv_u32 t = 0u; t < 8u; ++t) MV_ST(class_mask, 8u * r + t, mv_reflect_mask(c, t));
    if (p.leaf == 2u) MV_ST(idnorm, r, MV_LD(table, 2u * c + 1u)); /* a reflection keeps the stabilizer */
  }
}

MV_INLINE void mv_leaf_ids(MvBufU32 mask, MvBufU32 table, MvBufU32 rank, MvBufU32 id, MvBufU32 tag, MvDagParams p,
                           mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 m = MV_LD(mask, i);
    if (p.leaf == 2u) {
      mv_u32 e = MV_LD(table, 2u * m);
      MV_ST(id, i, MV_LD(rank, e & 0xffu));
      MV_ST(tag, i, (e >> 11) & 7u);
    } else {
      MV_ST(id, i, MV_LD(rank, m));
    }
  }
}

#endif

/* Symmetry-aware DAG reduction (SSVDAG): subtrees equal up to the 8 reflections about the axis-aligned
 * planes through a node's centre share one representative; pointers carry a 3-bit reflection tag.
 *
 * The exact stabilizer method (notes on Jaspe Villanueva 2018, 1.6(c)). A reflection T is a 3-bit mask
 * (bit 0 = x, 1 = y, 2 = z) and, with Morton octants, maps octant c to c ^ T. Every representative keeps
 * stab = the set of reflections that leave it unchanged (an 8-bit set); a tag t on a pointer to it is
 * normalized to min over s in stab of t ^ s, so equal subtrees always get equal (id, tag) pairs. For node n
 * and each T, the reflected node n_T has child[c ^ T] = child[c] with tag norm(tag[c] ^ T). n's class is
 * keyed by Key(n_T*) with T* = argmin_T Key(n_T) (mask, then tags by octant, then ids by octant), stab(n) =
 * {S : Key(n_S) == Key(n_0)}, and the parent's pointer to n becomes (class, norm(T*)). Each node keeps that
 * tag as a row: field k = norm(tag ^ k), the tag seen through reflection k, so its parent never looks up the
 * child class's stabilizer (a random read per child). Level-1 nodes (2x2x2 masks) are keyed by the mask
 * alone (a 256-entry table), level-2 nodes by their 4x4x4 brick (64 exact bits, ordered by (mask, brick):
 * another total order, as exact; equal bricks are grouped before one per group is canonicalized). Exact: two
 * subtrees get the same key iff one is a reflection of the other, so no symmetry is missed. The hash / sort /
 * runs / verify pipeline of dag.h then assigns ids (bricks need no hash and no verification). */
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

/* T* (smallest key, ties to the smaller T) and stabilizer of each node above level 2 from its children's
 * (id, tag row) read once (mtab: leaf_table, which describes every 8-bit mask), and the hash of the canonical
 * key Key(n_T*) (seeded by p.seed_lo) for the sort that groups equal keys. With contiguous blocks (p.block), a
 * node equal to the one before it (flat faces repeat node after node) takes its results without the search. */
MV_INLINE void mv_ssvdag_canon(MvBufU32 mask, MvBufU32 mtab, MvBufU32 first, MvBufU32 cid, MvBufU32 crow,
                               MvBufU32 row_out, MvBufU64 hashes, MvBufU32 order, MvDagParams p,
                               mv_u32 gid, mv_u32 stride) {
  mv_u32 begin = p.block != 0u ? gid * p.block : gid;
  mv_u32 end = p.block != 0u ? MV_MIN(p.n, begin + p.block) : p.n;
  mv_u32 step = p.block != 0u ? 1u : stride;
  mv_u32 pm = 0u, pid[8], prow[8], orient = 0u; /* the previous node (pm = 0: none) and its results */
  mv_u64 h = MV_U64(0);
  for (mv_u32 c = 0u; c < 8u; ++c) {
    pid[c] = 0u;
    prow[c] = 0u;
  }
  for (mv_u32 i = begin; i < end; i += step) {
    mv_u32 m = MV_LD(mask, i);
    mv_u32 id[8], row[8]; /* row[c] field k: child c's tag seen through reflection k */
    mv_u32 j = MV_LD(first, i);
    bool again = m == pm;
    for (mv_u32 c = 0u; c < 8u; ++c) {
      id[c] = 0u;
      row[c] = 0u;
      if (((m >> c) & 1u) != 0u) {
        id[c] = MV_LD(cid, j);
        row[c] = MV_LD(crow, j);
        j += 1u;
      }
      again = again && id[c] == pid[c] && row[c] == prow[c];
    }
    if (again) {
      MV_ST(row_out, i, orient);
      MV_ST(hashes, i, h);
      MV_ST(order, i, i);
      continue;
    }
    pm = m;
    for (mv_u32 c = 0u; c < 8u; ++c) {
      pid[c] = id[c];
      prow[c] = row[c];
    }
    /* Only reflections that give the smallest mask can be T*, only those that fix the mask can fix the node:
     * the mask table gives the mask's own T* (t0) and stabilizer (ms); asymmetric masks need no entries. The
     * candidates n_t, t = t0 ^ g for g in ms, share the mask; they are ordered by their tags (octant 0's
     * first: 3 bits each, packed, so they compare as integers), then by their ids; n_t equals n_t0 iff
     * t0 ^ t fixes n. */
    mv_u32 info = MV_LD(mtab, mv_mask_info_at(m));
    mv_u32 mb = mv_mask_canonical(info), t0 = mv_mask_tstar(info), ms = mv_mask_stabilizer(info);
    mv_u32 best = t0, s = 1u;
    if (ms != 1u) {
      mv_u32 first_id = id[MV_FIND_MSB(m)]; /* flat faces: often one child subtree */
      bool one_id = true;
      for (mv_u32 c = 0u; c < 8u; ++c) one_id = one_id && (((m >> c) & 1u) == 0u || id[c] == first_id);
      mv_u32 base = 0u, lowest = 0u;
      for (mv_u32 g = 0u; g < 8u; ++g) {
        if (((ms >> g) & 1u) == 0u) continue;
        mv_u32 t = t0 ^ g, k = 0u;
        for (mv_u32 c = 0u; c < 8u; ++c) k |= mv_row_field(row[c], t) << (3u * (7u - c));
        k = mv_xor_fields(k, t); /* octant o's field moves to o ^ t */
        if (g == 0u) {
          base = k;
          lowest = k;
          continue;
        }
        mv_i32 vs = k < lowest ? -1 : (k > lowest ? 1 : 0); /* n_t against n_best */
        bool same = k == base;                               /* n_t against n_t0 */
        for (mv_u32 o = 0u; o < 8u && !one_id && (vs == 0 || same); ++o) { /* equal tags: the ids decide */
          mv_u32 c = o ^ t;
          if (((m >> c) & 1u) == 0u) continue;
          if (vs == 0 && id[c] != id[o ^ best]) vs = id[c] < id[o ^ best] ? -1 : 1;
          if (same && id[c] != id[o ^ t0]) same = false;
        }
        if (vs < 0 || (vs == 0 && t < best)) {
          lowest = k;
          best = t;
        }
        if (same) s |= 1u << g;
      }
    }
    orient = mv_orientation(mtab, best, s);
    MV_ST(row_out, i, orient);
    /* hash of the canonical key: mask, then the entries of n_T* in its present octants */
    h = (MV_U64(p.seed_hi) << 32) | MV_U64(p.seed_lo);
    h = mv_hash_mix(h, MV_U64(mb));
    for (mv_u32 o = 0u; o < 8u; ++o) {
      mv_u32 c = o ^ best;
      if (((m >> c) & 1u) != 0u)
        h = mv_hash_mix(h, mv_entry(id[c], mv_row_field(row[c], best)));
    }
    MV_ST(hashes, i, h);
    MV_ST(order, i, i);
  }
}

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

/* Canonical keys of node i and its run's representative equal? A mismatch is a hash collision. The keys
 * are rebuilt from the children and each node's T* (cheaper than storing nine words per node). */
MV_INLINE void mv_ssvdag_verify(MvBufU32 mask, MvBufU32 first, MvBufU32 cid, MvBufU32 crow, MvBufU32 row,
                                MvBufU32 id, MvBufU32 rep, MvBufU32 collided, MvDagParams p, mv_u32 gid,
                                mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 r = MV_LD(rep, MV_LD(id, i));
    if (r == i) continue;
    mv_u32 ti = mv_row_tstar(MV_LD(row, i)), tr = mv_row_tstar(MV_LD(row, r));
    mv_u32 m = MV_LD(mask, i), mr = MV_LD(mask, r), j = MV_LD(first, i);
    bool same = mv_reflect_mask(m, ti) == mv_reflect_mask(mr, tr);
    for (mv_u32 c = 0u; c < 8u && same; ++c) { /* i's child c against the rep's child at the same octant */
      if (((m >> c) & 1u) == 0u) continue;
      mv_u32 id = MV_LD(cid, j);
      mv_u32 cr = c ^ ti ^ tr, jr = MV_LD(first, r) + mv_popcount8(mr & ((1u << cr) - 1u));
      mv_u32 idr = MV_LD(cid, jr);
      same = id == idr && mv_norm_tag(ti, MV_LD(crow, j)) == mv_norm_tag(tr, MV_LD(crow, jr));
      j += 1u;
    }
    if (!same) MV_ST(collided, 0u, 1u);
  }
}

/* The reduced level in id order, for the host: class r's stored mask (its representative reflected by T*)
 * and its 8 entries (mv_entry) in octant order. p.seed_lo = 1 with symmetry; without
 * it row and crow are null and tags are 0. */
MV_INLINE void mv_dag_emit(MvBufU32 mask, MvBufU32 first, MvBufU32 cid, MvBufU32 crow, MvBufU32 row, MvBufU32 rep,
                           MvBufU32 out_mask, MvBufU64 out_entry, MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 r = gid; r < p.n; r += stride) {
    mv_u32 node = MV_LD(rep, r);
    mv_u32 t = p.seed_lo != 0u ? mv_row_tstar(MV_LD(row, node)) : 0u; /* seed_lo: 1 = symmetric */
    MV_ST(out_mask, r, mv_reflect_mask(MV_LD(mask, node), t));
    if (p.leaf != 0u) continue;
    mv_u32 m = MV_LD(mask, node), j = MV_LD(first, node);
    for (mv_u32 c = 0u; c < 8u; ++c) { /* child c lands at octant c ^ t; each child read once */
      mv_u64 e = MV_U64(0);
      if (((m >> c) & 1u) != 0u) {
        mv_u32 tag = 0u;
        if (p.seed_lo != 0u) tag = mv_norm_tag(t, MV_LD(crow, j));
        e = mv_entry(MV_LD(cid, j), tag);
        j += 1u;
      }
      MV_ST(out_entry, 8u * r + (c ^ t), e);
    }
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

#endif

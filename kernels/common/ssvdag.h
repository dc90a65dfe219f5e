/* Symmetry-aware DAG reduction (SSVDAG): subtrees equal up to the 8 reflections about the axis-aligned
 * planes through a node's centre share one representative; pointers carry a 3-bit reflection tag.
 *
 * The exact stabilizer method (Jaspe Villanueva, PhD thesis, A Coruna 2018, ch. 5, inner-node matching). A
 * reflection T is a 3-bit mask (bit 0 = x, 1 = y, 2 = z) and, with Morton octants, maps octant c to c ^ T. Every
 * representative keeps stab = the set of reflections that leave it unchanged (an 8-bit set); a tag t on a pointer
 * to it is normalized to min over s in stab of t ^ s, so equal subtrees always get equal (id, tag) pairs. For node
 * n and each T, the reflected node n_T has child[c ^ T] = child[c] with tag norm(tag[c] ^ T). n's class is keyed by
 * Key(n_T*) with T* = argmin_T Key(n_T) (mask, then tags by octant, then ids by octant), stab(n) = {S : Key(n_S) ==
 * Key(n_0)}, and the parent's pointer to n becomes (class, norm(T*)). Each node keeps that tag as a row: field k =
 * norm(tag ^ k), the tag seen through reflection k, so its parent never looks up the child class's stabilizer (a
 * random read per child). Level-1 nodes (2x2x2 masks) are keyed by the mask alone (a 256-entry table), level-2
 * nodes by their 4x4x4 brick (64 exact bits, ordered by (mask, brick): another total order, as exact; equal bricks
 * are grouped before one per group is canonicalized). Exact: two subtrees get the same key iff one is a reflection
 * of the other, so no symmetry is missed. The hash / sort / runs / verify pipeline of dag.h then assigns ids
 * (bricks need no hash and no verification). Parts: the tags and tables in ssvdag_tags.h, level 1 in
 * ssvdag_leaves.h, level 2 in ssvdag_bricks.h; here, the levels above 2 (canonical keys, verification, the emitted
 * level). */
#ifndef MV_SSVDAG_H
#define MV_SSVDAG_H
#include "ssvdag_bricks.h"
#include "ssvdag_leaves.h"
#include "ssvdag_tags.h"

/* T* (smallest key, ties to the smaller T) and stabilizer of each node above level 2 from its children's
 * (id, tag row) read once (mtab: leaf_table, which describes every 8-bit mask), and the hash of the canonical
 * key Key(n_T*) (seeded by p.seed_lo) for the sort that groups equal keys. With contiguous blocks (p.block), a
 * node equal to the one before it (flat faces repeat node after node) takes its results without the search. */
MV_INLINE void mv_ssvdag_canon(MvBufU32 mask, MvBufU32 mtab, MvBufU32 first, MvBufU32 cid, MvBufU32 crow,
                               MvBufU32 row_out, MvBufU64 hashes, MvBufU32 order, MvDagParams p,
                               mv_u32 gid, mv_u32 stride) {
  MvItems items = mv_items(p.block, gid, stride, p.n);
  mv_u32 begin = items.begin, end = items.end, step = items.step;
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
    MV_ST(hashes, i, mv_hash_kept(h, p.hash_drop));
    MV_ST(order, i, i);
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

#endif

/* Sparse voxel octree levels and DAG reduction, one level at a time, bottom-up.
 *
 * A level is a sorted array of node keys (Morton codes at that level; level 0 = voxels). Parents are the
 * distinct key >> 3, each with an 8-bit child mask (bit = key & 7, the Morton octant: x lowest) and the index
 * of its first child; a node's children are contiguous in the level below, in octant order.
 *
 * Reduction of a level to its distinct subtrees: each node hashes (mask, ids of its children); (hash, node)
 * pairs are radix-sorted; runs of equal hashes become ids (in hash order, so every backend gives the same
 * ids); every node is then compared with its run's first node and any mismatch (a hash collision) is
 * reported, upon which the host repeats the level with another seed. Exact, and nothing waits on another
 * work-group. */
#ifndef MV_DAG_H
#define MV_DAG_H
#include "mv_lang.h"

MV_STRUCT_BEGIN(MvDagParams)
  mv_u32 n;     /* nodes (or keys) in this level */
  mv_u32 leaf;  /* nonzero: level-1 nodes, whose identity is the mask alone (2: with symmetry) */
  mv_u32 seed_lo;
  mv_u32 seed_hi;
  mv_u32 block; /* ssvdag_canon: nodes per work-item, contiguous (CPU devices); 0 = grid-stride */
  mv_u32 hash_drop; /* high bits cleared from node hashes (0 in builds): lets tests force hash collisions */
MV_STRUCT_END(MvDagParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvDagParams, 24);
MV_LAYOUT_AT(MvDagParams, n, 0); MV_LAYOUT_AT(MvDagParams, leaf, 4); MV_LAYOUT_AT(MvDagParams, seed_lo, 8);
MV_LAYOUT_AT(MvDagParams, seed_hi, 12); MV_LAYOUT_AT(MvDagParams, block, 16); MV_LAYOUT_AT(MvDagParams, hash_drop, 20);
#endif

/* A node hash with its p.hash_drop high bits cleared (at most 63). */
MV_INLINE mv_u64 mv_hash_kept(mv_u64 h, mv_u32 drop) {
  return h & (~MV_U64(0u) >> drop);
}

MV_INLINE mv_u32 mv_popcount8(mv_u32 m) {
  m = m - ((m >> 1) & 0x55u);
  m = (m & 0x33u) + ((m >> 2) & 0x33u);
  return (m + (m >> 4)) & 0x0fu;
}

MV_INLINE bool mv_parent_starts(MvBufU64 keys, mv_u32 i) {
  return i == 0u || (MV_LD(keys, i) >> 3) != (MV_LD(keys, i - 1u) >> 3);
}

MV_INLINE void mv_svo_flags(MvBufU64 keys, MvBufU32 flags, MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) MV_ST(flags, i, mv_parent_starts(keys, i) ? 1u : 0u);
}

/* pos: exclusive scan of the flags. Writes each parent's key, child mask and first child. */
MV_INLINE void mv_svo_parents(MvBufU64 keys, MvBufU32 pos, MvBufU64 pkeys, MvBufU32 pmask, MvBufU32 pfirst,
                              MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    if (!mv_parent_starts(keys, i)) continue;
    mv_u64 parent = MV_LD(keys, i) >> 3;
    mv_u32 mask = 0u;
    for (mv_u32 j = i; j < MV_MIN(i + 8u, p.n); ++j)
      if ((MV_LD(keys, j) >> 3) == parent) mask |= 1u << MV_U32(MV_LD(keys, j) & MV_U64(7));
    mv_u32 at = MV_LD(pos, i);
    MV_ST(pkeys, at, parent);
    MV_ST(pmask, at, mask);
    MV_ST(pfirst, at, i);
  }
}

/* The octree's bottom from 4^3 bricks (sorted unique brick keys with 64-bit masks; bit i = the voxel at Morton
 * index i inside the brick, so byte o is the 2^3 mask of octant o): level 2 is the bricks themselves. Pass 1:
 * each brick's level-2 mask (octant o present iff byte o is not 0) and its child count; pass 2, at the
 * scanned first children: the level-1 masks, the non-zero bytes in octant order. */
MV_INLINE mv_u32 mv_brick_octants(mv_u64 m) {
  mv_u32 mask = 0u;
  for (mv_u32 o = 0u; o < 8u; ++o)
    if (((m >> (8u * o)) & MV_U64(0xffu)) != MV_U64(0u)) mask |= 1u << o;
  return mask;
}
MV_INLINE void mv_brick_levels(MvBufU64 bricks, MvBufU32 mask2, MvBufU32 count, MvDagParams p, mv_u32 gid,
                               mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 m = mv_brick_octants(MV_LD(bricks, i));
    MV_ST(mask2, i, m);
    MV_ST(count, i, mv_popcount8(m));
  }
}
MV_INLINE void mv_brick_leaves(MvBufU64 bricks, MvBufU32 first2, MvBufU32 mask1, MvDagParams p, mv_u32 gid,
                               mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u64 m = MV_LD(bricks, i);
    mv_u32 at = MV_LD(first2, i);
    for (mv_u32 o = 0u; o < 8u; ++o) {
      mv_u32 b = MV_U32((m >> (8u * o)) & MV_U64(0xffu));
      if (b == 0u) continue;
      MV_ST(mask1, at, b);
      at += 1u;
    }
  }
}
/* dst[i] = src[order[i]]: the voxelizer's brick masks in the order their sorted keys took. */
MV_INLINE void mv_brick_gather(MvBufU64 src, MvBufU32 order, MvBufU64 dst, MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) MV_ST(dst, i, MV_LD(src, MV_LD(order, i)));
}

MV_INLINE mv_u64 mv_hash_mix(mv_u64 h, mv_u64 x) {
  h ^= x + MV_U64(0x9e3779b97f4a7c15UL) + (h << 6) + (h >> 2);
  h ^= h >> 31;
  h *= MV_U64(0xbf58476d1ce4e5b9UL);
  h ^= h >> 29;
  return h;
}

/* Node i's identity hash: its mask and, above level 1, the ids of its children (cid: id per node below). */
MV_INLINE mv_u64 mv_node_hash(MvBufU32 mask, MvBufU32 first, MvBufU32 cid, MvDagParams p, mv_u32 i) {
  mv_u64 h = (MV_U64(p.seed_hi) << 32) | MV_U64(p.seed_lo);
  mv_u32 m = MV_LD(mask, i);
  h = mv_hash_mix(h, MV_U64(m));
  if (p.leaf == 0u) {
    mv_u32 f = MV_LD(first, i);
    mv_u32 c = mv_popcount8(m);
    for (mv_u32 r = 0u; r < c; ++r) h = mv_hash_mix(h, MV_U64(MV_LD(cid, f + r)));
  }
  return mv_hash_kept(h, p.hash_drop);
}

MV_INLINE bool mv_same_node(MvBufU32 mask, MvBufU32 first, MvBufU32 cid, MvDagParams p, mv_u32 a, mv_u32 b) {
  mv_u32 m = MV_LD(mask, a);
  if (m != MV_LD(mask, b)) return false;
  if (p.leaf != 0u) return true;
  mv_u32 fa = MV_LD(first, a), fb = MV_LD(first, b);
  bool same = true;
  for (mv_u32 r = 0u; r < mv_popcount8(m); ++r) same = same && MV_LD(cid, fa + r) == MV_LD(cid, fb + r);
  return same;
}

MV_INLINE void mv_dag_hash(MvBufU32 mask, MvBufU32 first, MvBufU32 cid, MvBufU64 hashes, MvBufU32 order,
                           MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    MV_ST(hashes, i, mv_node_hash(mask, first, cid, p, i));
    MV_ST(order, i, i);
  }
}

/* After sorting: flags[i] = 1 where sorted position i starts a run of equal hashes. */
MV_INLINE void mv_dag_runs(MvBufU64 hashes, MvBufU32 flags, MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride)
    MV_ST(flags, i, (i == 0u || MV_LD(hashes, i) != MV_LD(hashes, i - 1u)) ? 1u : 0u);
}

/* run: exclusive scan of the run flags. Node order[i] gets id = its run; each run's first node becomes the
 * run's representative. */
MV_INLINE void mv_dag_assign(MvBufU64 hashes, MvBufU32 order, MvBufU32 run, MvBufU32 id, MvBufU32 rep,
                             MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    bool head = i == 0u || MV_LD(hashes, i) != MV_LD(hashes, i - 1u);
    mv_u32 r = head ? MV_LD(run, i) : MV_LD(run, i) - 1u;
    MV_ST(id, MV_LD(order, i), r);
    if (head) MV_ST(rep, r, MV_LD(order, i));
  }
}

/* Any node unequal to its run's representative is a hash collision: collided[0] = 1. */
MV_INLINE void mv_dag_verify(MvBufU32 mask, MvBufU32 first, MvBufU32 cid, MvBufU32 id, MvBufU32 rep,
                             MvBufU32 collided, MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride)
    if (!mv_same_node(mask, first, cid, p, i, MV_LD(rep, MV_LD(id, i)))) MV_ST(collided, 0u, 1u);
}

/* Eight 3-bit fields with fields k and k ^ t swapped (field k of the result = field k ^ t of x). */
MV_INLINE mv_u32 mv_xor_fields(mv_u32 x, mv_u32 t) {
  if ((t & 1u) != 0u) x = ((x & 0x1c71c7u) << 3) | ((x >> 3) & 0x1c71c7u);
  if ((t & 2u) != 0u) x = ((x & 0x03f03fu) << 6) | ((x >> 6) & 0x03f03fu);
  if ((t & 4u) != 0u) x = ((x & 0x000fffu) << 12) | ((x >> 12) & 0x000fffu);
  return x;
}

/* Out-of-core merge: a union of partial DAGs is reduced again like an octree level whose "children" are
 * pointer slots. Each slot takes the class id of the node it points to and, with symmetry (p.leaf = 1), the
 * tag row of its own tag composed with that node's (row field k = norm(slot tag ^ node tag ^ k); ssvdag.h). */
MV_INLINE void mv_gather_slots(MvBufU32 slot_node, MvBufU32 slot_tag, MvBufU32 id, MvBufU32 row, MvBufU32 out_id,
                               MvBufU32 out_row, MvDagParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 s = gid; s < p.n; s += stride) {
    mv_u32 node = MV_LD(slot_node, s);
    MV_ST(out_id, s, MV_LD(id, node));
    if (p.leaf != 0u) MV_ST(out_row, s, mv_xor_fields(MV_LD(row, node), MV_LD(slot_tag, s)));
  }
}

#endif

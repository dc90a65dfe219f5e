/* The Boykov-Kolmogorov min-cut over regions (min_cut_regions.h): what it keeps in memory and shares with the
 * host. A pixel's node words, a region's state words and its steps (the host starts and reads the state machine
 * through them), the parameters, and the small helpers and queue macros the steps use. */
#ifndef MV_MIN_CUT_REGIONS_LAYOUT_H
#define MV_MIN_CUT_REGIONS_LAYOUT_H
#include "grid_graph.h"

/* A pixel's words in node[], side by side so that a walk or a growth touching a pixel loads one cache line:
 * - tree: bits 0-3 the direction to the parent (0..7), MV_BK_ROOT (the parent is the pixel's terminal),
 *   MV_BK_ORPHAN or MV_BK_FREE; MV_BK_SINK set in the sink's tree;
 * - ts, dist: Kolmogorov's time stamp and the distance to the terminal it vouches for;
 * - parent: the parent pixel's index (valid while the direction is), so that a walk's next pixel is one load
 *   away: computing it from the direction put a multiply and the decode on the walk's chain of dependent loads,
 *   and walks are most of the time (they take a third less with the index stored).
 * The active queue links through next[] (MV_BK_NONE: not queued), apart: it is touched far less often. */
#define MV_BK_NODE_WORDS 4u
#define MV_BK_TREE(i) ((i) * MV_BK_NODE_WORDS)
#define MV_BK_TS(i) ((i) * MV_BK_NODE_WORDS + 1u)
#define MV_BK_DIST(i) ((i) * MV_BK_NODE_WORDS + 2u)
#define MV_BK_PARENT(i) ((i) * MV_BK_NODE_WORDS + 3u)
#define MV_BK_ROOT 8u
#define MV_BK_ORPHAN 9u
#define MV_BK_FREE 10u
#define MV_BK_SINK 16u
#define MV_BK_NONE 0xffffffffu /* no pixel (next[i]: not queued as active) */

/* Words of a region's state (state[region * MV_BK_STATE_WORDS + k]). */
#define MV_BK_STATE_WORDS 20u
#define MV_BK_W_STEP 0u    /* which step runs next (MV_BK_*) */
#define MV_BK_W_K 1u       /* the pixel a start step has reached */
#define MV_BK_W_I 2u       /* the active pixel growing its tree */
#define MV_BK_W_D 3u       /* the next edge an adoption looks at */
#define MV_BK_W_CUR 4u     /* the pixel that augmented last, grown again next (Kolmogorov's current node) */
#define MV_BK_W_U 5u       /* the augmenting path's edge between the trees: from U (source tree) along UD */
#define MV_BK_W_UD 6u
#define MV_BK_W_X 7u       /* where a walk is */
#define MV_BK_W_B 8u       /* the path's bottleneck */
#define MV_BK_W_O 9u       /* the orphan being adopted */
#define MV_BK_W_DD 10u     /* the edge to the candidate parent a walk checks */
#define MV_BK_W_BEST 11u   /* the best parent found (direction), and its distance to the terminal */
#define MV_BK_W_DMIN 12u
#define MV_BK_W_DC 13u     /* the distance a walk counted */
#define MV_BK_W_HEAD 14u   /* the queue of active pixels, linked through next[] (the last one links to itself) */
#define MV_BK_W_TAIL 15u
#define MV_BK_W_TIME 16u   /* Kolmogorov's time stamp: ts[i] == time marks a distance found in this adoption */
#define MV_BK_W_OHEAD 17u  /* the orphans: a ring in orphans[] over the region's slice */
#define MV_BK_W_OCOUNT 18u
#define MV_BK_W_FLOW 19u   /* the flow the region augmented */

/* Steps. */
#define MV_BK_START 0u     /* k: set the region's words, and queue its pixels with a terminal edge as roots */
#define MV_BK_SEAMS 1u     /* k: queue the tree pixels beside the seams between the region's four parts */
#define MV_BK_PICK 2u      /* take the next active pixel */
#define MV_BK_GROW 3u      /* i: grow i's tree along its edges */
#define MV_BK_NECK_S 4u    /* x: the bottleneck on the source side, walking to the root */
#define MV_BK_NECK_T 5u    /* x: the same on the sink side */
#define MV_BK_PUSH_S 6u    /* x: push the bottleneck along the source side; saturated edges leave orphans */
#define MV_BK_PUSH_T 7u
#define MV_BK_ORPHANS 8u   /* take the next orphan */
#define MV_BK_ADOPT 9u     /* o, d: look at o's neighbour d as a parent */
#define MV_BK_WALK 10u     /* x, dc: walk from the candidate to its root (or to a distance known this time) */
#define MV_BK_MARK 11u     /* x, dc: stamp the walk's pixels with their distances */
#define MV_BK_FREE_O 12u   /* o: o has no parent: free it, wake its neighbours, orphan its children */
#define MV_BK_DONE 13u

MV_STRUCT_BEGIN(MvMinCutRegionsParams)
  mv_u32 width;
  mv_u32 height;
  mv_u32 conn;       /* 4 or 8 */
  mv_u32 regions_x;  /* the first level's regions across and down */
  mv_u32 regions_y;
  mv_u32 group;      /* a region of this level is group x group regions of the first (1, 2, 4, ...) */
  mv_u32 budget;     /* steps per item per dispatch */
  mv_u32 walk;       /* pixels a walk takes per step */
MV_STRUCT_END(MvMinCutRegionsParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvMinCutRegionsParams, 32);
MV_LAYOUT_AT(MvMinCutRegionsParams, width, 0); MV_LAYOUT_AT(MvMinCutRegionsParams, height, 4);
MV_LAYOUT_AT(MvMinCutRegionsParams, conn, 8); MV_LAYOUT_AT(MvMinCutRegionsParams, regions_x, 12);
MV_LAYOUT_AT(MvMinCutRegionsParams, regions_y, 16); MV_LAYOUT_AT(MvMinCutRegionsParams, group, 20);
MV_LAYOUT_AT(MvMinCutRegionsParams, budget, 24); MV_LAYOUT_AT(MvMinCutRegionsParams, walk, 28);
#endif

/* Where part a of `parts` equal parts of [0, size) starts (the first size % parts parts one longer). */
MV_INLINE mv_u32 mv_bk_split(mv_u32 size, mv_u32 parts, mv_u32 a) {
  return a * (size / parts) + MV_MIN(a, size % parts);
}

/* Pixel i's neighbour d (the caller knows it is on the grid). */
MV_INLINE mv_u32 mv_bk_step(MvMinCutRegionsParams p, mv_u32 i, mv_u32 d) {
  return MV_U32(MV_I32(i) + mv_grid_dy(d) * MV_I32(p.width) + mv_grid_dx(d));
}

/* Whether pixel (x, y) lies in the rectangle [x0, x1) x [y0, y1). */
MV_INLINE bool mv_bk_in(mv_i32 x, mv_i32 y, mv_u32 x0, mv_u32 y0, mv_u32 x1, mv_u32 y1) {
  return x >= MV_I32(x0) && y >= MV_I32(y0) && x < MV_I32(x1) && y < MV_I32(y1);
}

/* The capacity that lets pixel i's tree (sink: the sink's) reach or hold its neighbour j = i + d: from i to j in
 * the source's tree, from j to i in the sink's. */
MV_INLINE mv_u32 mv_bk_tree_cap(MvBufU32 resid, MvMinCutRegionsParams p, mv_u32 i, mv_u32 j, mv_u32 d, bool sink) {
  return sink ? MV_LD(resid, j * p.conn + (d ^ 1u)) : MV_LD(resid, i * p.conn + d);
}

/* Appends pixel j to the active queue unless it is queued (or is the current pixel: next[cur] == cur). */
#define MV_BK_ACTIVATE(j)                                                                                         \
  if (MV_LD(next, j) == MV_BK_NONE) {                                                                             \
    if (tail != MV_BK_NONE) MV_ST(next, tail, j);                                                                 \
    else head = (j);                                                                                              \
    tail = (j);                                                                                                   \
    MV_ST(next, j, j);                                                                                            \
  }
/* Makes pixel v an orphan, first or last in the ring. */
#define MV_BK_ORPHAN_FRONT(v)                                                                                     \
  {                                                                                                               \
    ohead = ohead == 0u ? size - 1u : ohead - 1u;                                                                 \
    MV_ST(orphans, base + ohead, v);                                                                              \
    ++ocount;                                                                                                     \
    MV_ST(node, MV_BK_TREE(v), (MV_LD(node, MV_BK_TREE(v)) & MV_BK_SINK) | MV_BK_ORPHAN);                         \
  }
#define MV_BK_ORPHAN_REAR(v)                                                                                      \
  {                                                                                                               \
    MV_ST(orphans, base + (ohead + ocount < size ? ohead + ocount : ohead + ocount - size), v);                   \
    ++ocount;                                                                                                     \
    MV_ST(node, MV_BK_TREE(v), (MV_LD(node, MV_BK_TREE(v)) & MV_BK_SINK) | MV_BK_ORPHAN);                         \
  }

/* The regions of a level across (down: mv_bk_level_regions(p.regions_y, p.group)). */
MV_INLINE mv_u32 mv_bk_level_regions(mv_u32 first, mv_u32 group) {
  return (first + group - 1u) / group;
}

#endif /* MV_MIN_CUT_REGIONS_LAYOUT_H */

/* Exact min-cut of a pixel-grid graph (grid_graph.h) by Boykov-Kolmogorov over regions, steps driven by the host.
 *
 * Boykov and Kolmogorov grow two search trees, one from the source and one from the sink, along residual
 * edges; where they meet, the path through both is augmented, and the pixels it cut off (orphans) find new
 * parents in their tree or become free. It ends when neither tree can grow: the source tree is then the set
 * of pixels reachable from the source in the residual graph, the canonical minimal source set.
 * Here the grid is first cut into rectangular regions, one work-item each, which solve their own pixels with
 * the edges between regions left out (every region at once: they share no pixel and no edge). Then each level
 * merges 2 x 2 regions of the level before into one, until one region is the whole grid (Liu and Sun's
 * bottom-up merging): a merged region continues from the trees its four parts left, which are trees of the
 * whole graph too, and only the pixels beside the seams between its parts have edges they have not looked at,
 * so those start active. The regions of a level run side by side.
 *
 * The algorithm is sequential inside a region, so every device takes the same steps and leaves the same bits.
 * Tree walks (to a root, along an augmenting path) have no bound but the region's size, and lavapipe stops an
 * invocation's loops after 65535 iterations, all its loops counted together: so an item runs a state machine,
 * one small step per iteration of a single loop (a step may loop over a pixel's edges, or over p.walk pixels of
 * a walk), for p.budget steps, keeps its state in `state`, and the host runs it again until it is done.
 *
 * Capacities follow the graph's direction: resid[i * conn + d] is what is left of the edge from pixel i to
 * its neighbour d; term[i] (signed) what is left of the source's edge to i (> 0) or of i's edge to the sink
 * (< 0) once the two have cancelled. The host keeps the total capacity below 2^31, so nothing overflows. */
#ifndef MV_MIN_CUT_BK_H
#define MV_MIN_CUT_BK_H
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

MV_STRUCT_BEGIN(MvMinCutBkParams)
  mv_u32 width;
  mv_u32 height;
  mv_u32 conn;       /* 4 or 8 */
  mv_u32 regions_x;  /* the first level's regions across and down */
  mv_u32 regions_y;
  mv_u32 group;      /* a region of this level is group x group regions of the first (1, 2, 4, ...) */
  mv_u32 budget;     /* steps per item per dispatch */
  mv_u32 walk;       /* pixels a walk takes per step */
MV_STRUCT_END(MvMinCutBkParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvMinCutBkParams, 32);
MV_LAYOUT_AT(MvMinCutBkParams, width, 0); MV_LAYOUT_AT(MvMinCutBkParams, height, 4);
MV_LAYOUT_AT(MvMinCutBkParams, conn, 8); MV_LAYOUT_AT(MvMinCutBkParams, regions_x, 12);
MV_LAYOUT_AT(MvMinCutBkParams, regions_y, 16); MV_LAYOUT_AT(MvMinCutBkParams, group, 20);
MV_LAYOUT_AT(MvMinCutBkParams, budget, 24); MV_LAYOUT_AT(MvMinCutBkParams, walk, 28);
#endif

/* Where part a of `parts` equal parts of [0, size) starts (the first size % parts parts one longer). */
MV_INLINE mv_u32 mv_bk_split(mv_u32 size, mv_u32 parts, mv_u32 a) {
  return a * (size / parts) + MV_MIN(a, size % parts);
}

/* Pixel i's neighbour d (the caller knows it is on the grid). */
MV_INLINE mv_u32 mv_bk_step(MvMinCutBkParams p, mv_u32 i, mv_u32 d) {
  return MV_U32(MV_I32(i) + mv_grid_dy(d) * MV_I32(p.width) + mv_grid_dx(d));
}

/* Whether pixel (x, y) lies in the rectangle [x0, x1) x [y0, y1). */
MV_INLINE bool mv_bk_in(mv_i32 x, mv_i32 y, mv_u32 x0, mv_u32 y0, mv_u32 x1, mv_u32 y1) {
  return x >= MV_I32(x0) && y >= MV_I32(y0) && x < MV_I32(x1) && y < MV_I32(y1);
}

/* The capacity that lets pixel i's tree (sink: the sink's) reach or hold its neighbour j = i + d: from i to j in
 * the source's tree, from j to i in the sink's. */
MV_INLINE mv_u32 mv_bk_tree_cap(MvBufU32 resid, MvMinCutBkParams p, mv_u32 i, mv_u32 j, mv_u32 d, bool sink) {
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

/* Runs region r of the level p.group says for `budget` steps at most from state[], stores the state back, and
 * returns the steps it took. */
MV_INLINE mv_u32 mv_bk_run(MvBufU32 resid, MvBufU32 term, MvBufU32 node, MvBufU32 next, MvBufU32 orphans,
                           MvBufU32 state, MvMinCutBkParams p, mv_u32 r, mv_u32 budget) {
  mv_u32 at = r * MV_BK_STATE_WORDS;
  mv_u32 op = MV_LD(state, at + MV_BK_W_STEP);
  if (op == MV_BK_DONE) return 0u;
  /* The region's rectangle (the first level's regions ga..gb across, gc..gd down), and its slice of orphans[]
   * (regions in row order cover [0, n) in turn). */
  mv_u32 rx = mv_bk_level_regions(p.regions_x, p.group);
  mv_u32 ga = r % rx * p.group, gb = MV_MIN(ga + p.group, p.regions_x);
  mv_u32 gc = r / rx * p.group, gd = MV_MIN(gc + p.group, p.regions_y);
  mv_u32 x0 = mv_bk_split(p.width, p.regions_x, ga), x1 = mv_bk_split(p.width, p.regions_x, gb);
  mv_u32 y0 = mv_bk_split(p.height, p.regions_y, gc), y1 = mv_bk_split(p.height, p.regions_y, gd);
  mv_u32 base = y0 * p.width + x0 * (y1 - y0);
  mv_u32 size = (x1 - x0) * (y1 - y0);
  mv_u32 k = MV_LD(state, at + MV_BK_W_K), i = MV_LD(state, at + MV_BK_W_I), d = MV_LD(state, at + MV_BK_W_D);
  mv_u32 cur = MV_LD(state, at + MV_BK_W_CUR), u = MV_LD(state, at + MV_BK_W_U), ud = MV_LD(state, at + MV_BK_W_UD);
  mv_u32 x = MV_LD(state, at + MV_BK_W_X), b = MV_LD(state, at + MV_BK_W_B), o = MV_LD(state, at + MV_BK_W_O);
  mv_u32 dd = MV_LD(state, at + MV_BK_W_DD), best = MV_LD(state, at + MV_BK_W_BEST);
  mv_u32 dmin = MV_LD(state, at + MV_BK_W_DMIN), dc = MV_LD(state, at + MV_BK_W_DC);
  mv_u32 head = MV_LD(state, at + MV_BK_W_HEAD), tail = MV_LD(state, at + MV_BK_W_TAIL);
  mv_u32 time = MV_LD(state, at + MV_BK_W_TIME), ohead = MV_LD(state, at + MV_BK_W_OHEAD);
  mv_u32 ocount = MV_LD(state, at + MV_BK_W_OCOUNT), flow = MV_LD(state, at + MV_BK_W_FLOW);
  mv_u32 s = 0u;
  for (; s < budget && op != MV_BK_DONE; ++s) {
    /* The steps, the most frequent first. */
    if (op == MV_BK_WALK) {
      for (mv_u32 w = 0u; w < p.walk; ++w) {
        bool rooted = true;
        if (MV_LD(node, MV_BK_TS(x)) == time) { /* a distance found earlier in this adoption */
          dc += MV_LD(node, MV_BK_DIST(x));
        } else {
          ++dc;
          mv_u32 px = MV_LD(node, MV_BK_TREE(x)) & 15u;
          if (px == MV_BK_ORPHAN) { /* not rooted: no parent */
            op = MV_BK_ADOPT;
            break;
          }
          if (px != MV_BK_ROOT) {
            x = MV_LD(node, MV_BK_PARENT(x));
            rooted = false;
          } else {
            MV_ST(node, MV_BK_TS(x), time);
            MV_ST(node, MV_BK_DIST(x), 1u);
          }
        }
        if (rooted) {
          if (dc < dmin) {
            best = dd;
            dmin = dc;
          }
          x = mv_bk_step(p, o, dd);
          op = MV_BK_MARK;
          break;
        }
      }
    } else if (op == MV_BK_MARK) {
      for (mv_u32 w = 0u; w < p.walk; ++w) {
        if (MV_LD(node, MV_BK_TS(x)) == time) {
          op = MV_BK_ADOPT;
          break;
        }
        MV_ST(node, MV_BK_TS(x), time);
        MV_ST(node, MV_BK_DIST(x), dc);
        --dc;
        x = MV_LD(node, MV_BK_PARENT(x));
      }
    } else if (op == MV_BK_ADOPT) {
      if (d == p.conn) {
        mv_u32 side = MV_LD(node, MV_BK_TREE(o)) & MV_BK_SINK;
        if (best != MV_BK_NONE) {
          MV_ST(node, MV_BK_TREE(o), side | best);
          MV_ST(node, MV_BK_PARENT(o), mv_bk_step(p, o, best));
          MV_ST(node, MV_BK_TS(o), time);
          MV_ST(node, MV_BK_DIST(o), dmin + 1u);
          op = MV_BK_ORPHANS;
        } else {
          MV_ST(node, MV_BK_TREE(o), side | MV_BK_FREE);
          op = MV_BK_FREE_O;
        }
        continue;
      }
      dd = d;
      ++d;
      if (!mv_bk_in(MV_I32(o % p.width) + mv_grid_dx(dd), MV_I32(o / p.width) + mv_grid_dy(dd), x0, y0, x1, y1)) continue;
      mv_u32 j = mv_bk_step(p, o, dd);
      mv_u32 to = MV_LD(node, MV_BK_TREE(o)), tj = MV_LD(node, MV_BK_TREE(j));
      if ((tj & MV_BK_SINK) != (to & MV_BK_SINK) || (tj & 15u) == MV_BK_FREE) continue;
      /* j may be o's parent where the edge holds o in the tree: j to o (source), o to j (sink) */
      if (mv_bk_tree_cap(resid, p, j, o, dd ^ 1u, (to & MV_BK_SINK) != 0u) == 0u) continue;
      x = j;
      dc = 0u;
      op = MV_BK_WALK;
    } else if (op == MV_BK_GROW) { /* all of i's edges in one step, up to the first that meets the other tree */
      mv_u32 ti = MV_LD(node, MV_BK_TREE(i));
      bool sink = (ti & MV_BK_SINK) != 0u;
      mv_i32 ix = MV_I32(i % p.width), iy = MV_I32(i / p.width);
      op = MV_BK_PICK;
      for (mv_u32 e = 0u; e < p.conn; ++e) {
        if (!mv_bk_in(ix + mv_grid_dx(e), iy + mv_grid_dy(e), x0, y0, x1, y1)) continue;
        mv_u32 j = mv_bk_step(p, i, e);
        if (mv_bk_tree_cap(resid, p, i, j, e, sink) == 0u) continue;
        mv_u32 tj = MV_LD(node, MV_BK_TREE(j));
        if ((tj & 15u) == MV_BK_FREE) { /* j joins i's tree, i its parent */
          MV_ST(node, MV_BK_TREE(j), (ti & MV_BK_SINK) | (e ^ 1u));
          MV_ST(node, MV_BK_PARENT(j), i);
          MV_ST(node, MV_BK_TS(j), MV_LD(node, MV_BK_TS(i)));
          MV_ST(node, MV_BK_DIST(j), MV_LD(node, MV_BK_DIST(i)) + 1u);
          MV_BK_ACTIVATE(j)
        } else if ((tj & MV_BK_SINK) != (ti & MV_BK_SINK)) { /* the trees meet: augment along the path */
          cur = i;
          MV_ST(next, i, i);
          u = sink ? j : i;
          ud = sink ? (e ^ 1u) : e;
          b = MV_LD(resid, u * p.conn + ud);
          x = u;
          op = MV_BK_NECK_S;
          break;
        } else if ((tj & 15u) < MV_BK_ROOT && MV_LD(node, MV_BK_TS(j)) <= MV_LD(node, MV_BK_TS(i)) &&
                   MV_LD(node, MV_BK_DIST(j)) > MV_LD(node, MV_BK_DIST(i))) {
          /* j is nearer its terminal through i (Kolmogorov's heuristic) */
          MV_ST(node, MV_BK_TREE(j), (ti & MV_BK_SINK) | (e ^ 1u));
          MV_ST(node, MV_BK_PARENT(j), i);
          MV_ST(node, MV_BK_TS(j), MV_LD(node, MV_BK_TS(i)));
          MV_ST(node, MV_BK_DIST(j), MV_LD(node, MV_BK_DIST(i)) + 1u);
        }
      }
      ++time;
    } else if (op == MV_BK_PICK) {
      if (cur != MV_BK_NONE) { /* the pixel that augmented last grows on, while it is in a tree */
        MV_ST(next, cur, MV_BK_NONE);
        i = cur;
        cur = MV_BK_NONE;
      } else {
        if (head == MV_BK_NONE) {
          op = MV_BK_DONE;
          continue;
        }
        i = head;
        mv_u32 after = MV_LD(next, i);
        if (after == i) head = tail = MV_BK_NONE;
        else head = after;
        MV_ST(next, i, MV_BK_NONE);
      }
      if ((MV_LD(node, MV_BK_TREE(i)) & 15u) != MV_BK_FREE) {
        op = MV_BK_GROW;
        d = 0u;
      }
    } else if (op == MV_BK_ORPHANS) {
      if (ocount == 0u) {
        op = MV_BK_PICK;
        continue;
      }
      o = MV_LD(orphans, base + ohead);
      ohead = ohead + 1u == size ? 0u : ohead + 1u;
      --ocount;
      d = 0u;
      best = MV_BK_NONE;
      dmin = MV_BK_NONE;
      op = MV_BK_ADOPT;
    } else if (op == MV_BK_NECK_S || op == MV_BK_NECK_T) { /* p.walk pixels of the walk per step */
      bool src = op == MV_BK_NECK_S;
      for (mv_u32 w = 0u; w < p.walk; ++w) {
        mv_u32 pd = MV_LD(node, MV_BK_TREE(x)) & 15u;
        if (pd == MV_BK_ROOT) {
          mv_i32 t = MV_I32(MV_LD(term, x));
          b = MV_MIN(b, MV_U32(src ? t : -t));
          if (src) {
            x = mv_bk_step(p, u, ud);
            op = MV_BK_NECK_T;
          } else {
            MV_ST(resid, u * p.conn + ud, MV_LD(resid, u * p.conn + ud) - b);
            mv_u32 v = mv_bk_step(p, u, ud);
            MV_ST(resid, v * p.conn + (ud ^ 1u), MV_LD(resid, v * p.conn + (ud ^ 1u)) + b);
            x = u;
            op = MV_BK_PUSH_S;
          }
          break;
        }
        mv_u32 par = MV_LD(node, MV_BK_PARENT(x));
        /* source side: the edge from the parent to x; sink side: from x to the parent */
        b = MV_MIN(b, src ? MV_LD(resid, par * p.conn + (pd ^ 1u)) : MV_LD(resid, x * p.conn + pd));
        x = par;
      }
    } else if (op == MV_BK_PUSH_S || op == MV_BK_PUSH_T) {
      bool src = op == MV_BK_PUSH_S;
      for (mv_u32 w = 0u; w < p.walk; ++w) {
        mv_u32 pd = MV_LD(node, MV_BK_TREE(x)) & 15u;
        if (pd == MV_BK_ROOT) {
          mv_i32 t = MV_I32(MV_LD(term, x)) + (src ? -MV_I32(b) : MV_I32(b));
          MV_ST(term, x, MV_U32(t));
          if (t == 0) MV_BK_ORPHAN_FRONT(x)
          if (src) {
            x = mv_bk_step(p, u, ud);
            op = MV_BK_PUSH_T;
          } else {
            flow += b;
            op = MV_BK_ORPHANS;
          }
          break;
        }
        mv_u32 par = MV_LD(node, MV_BK_PARENT(x));
        mv_u32 fwd = src ? par * p.conn + (pd ^ 1u) : x * p.conn + pd; /* the edge the flow runs along */
        mv_u32 back = src ? x * p.conn + pd : par * p.conn + (pd ^ 1u);
        mv_u32 left = MV_LD(resid, fwd) - b;
        MV_ST(resid, fwd, left);
        MV_ST(resid, back, MV_LD(resid, back) + b);
        if (left == 0u) MV_BK_ORPHAN_FRONT(x)
        x = par;
      }
    } else if (op == MV_BK_FREE_O) { /* all of o's edges in one step */
      mv_u32 to = MV_LD(node, MV_BK_TREE(o));
      mv_i32 ox = MV_I32(o % p.width), oy = MV_I32(o / p.width);
      for (mv_u32 e = 0u; e < p.conn; ++e) {
        if (!mv_bk_in(ox + mv_grid_dx(e), oy + mv_grid_dy(e), x0, y0, x1, y1)) continue;
        mv_u32 j = mv_bk_step(p, o, e);
        mv_u32 tj = MV_LD(node, MV_BK_TREE(j));
        if ((tj & MV_BK_SINK) != (to & MV_BK_SINK) || (tj & 15u) == MV_BK_FREE) continue;
        if (mv_bk_tree_cap(resid, p, j, o, e ^ 1u, (to & MV_BK_SINK) != 0u) != 0u) MV_BK_ACTIVATE(j)
        if ((tj & 15u) < MV_BK_ROOT && ((tj & 15u) ^ 1u) == e) MV_BK_ORPHAN_REAR(j) /* o was j's parent */
      }
      op = MV_BK_ORPHANS;
    } else if (op == MV_BK_START) { /* pixel k of the region, in row order: its words start here */
      if (k == size) {
        op = MV_BK_PICK;
        continue;
      }
      mv_u32 v = (y0 + k / (x1 - x0)) * p.width + x0 + k % (x1 - x0);
      mv_i32 t = MV_I32(MV_LD(term, v));
      MV_ST(node, MV_BK_TREE(v), t == 0 ? MV_BK_FREE : (t > 0 ? MV_BK_ROOT : (MV_BK_ROOT | MV_BK_SINK)));
      MV_ST(node, MV_BK_TS(v), 0u);
      MV_ST(node, MV_BK_DIST(v), 1u);
      MV_ST(next, v, MV_BK_NONE);
      if (t != 0) MV_BK_ACTIVATE(v)
      ++k;
    } else if (op == MV_BK_SEAMS) {
      /* Pixel k of the seams: the two columns either side of the boundary between the left and right parts,
       * every row, then the two rows either side of the one between the upper and lower parts (where the
       * region has two parts that way). */
      mv_u32 mid = p.group / 2u;
      mv_u32 columns = ga + mid < gb ? 2u * (y1 - y0) : 0u;
      mv_u32 rows = gc + mid < gd ? 2u * (x1 - x0) : 0u;
      if (k == columns + rows) {
        op = MV_BK_PICK;
        continue;
      }
      mv_u32 v;
      if (k < columns) {
        mv_u32 sx = mv_bk_split(p.width, p.regions_x, ga + mid) - 1u + (k & 1u);
        v = (y0 + k / 2u) * p.width + sx;
      } else {
        mv_u32 q = k - columns;
        mv_u32 sy = mv_bk_split(p.height, p.regions_y, gc + mid) - 1u + (q & 1u);
        v = sy * p.width + x0 + q / 2u;
      }
      if ((MV_LD(node, MV_BK_TREE(v)) & 15u) != MV_BK_FREE) MV_BK_ACTIVATE(v)
      ++k;
    }
  }
  MV_ST(state, at + MV_BK_W_STEP, op);
  MV_ST(state, at + MV_BK_W_K, k);
  MV_ST(state, at + MV_BK_W_I, i);
  MV_ST(state, at + MV_BK_W_D, d);
  MV_ST(state, at + MV_BK_W_CUR, cur);
  MV_ST(state, at + MV_BK_W_U, u);
  MV_ST(state, at + MV_BK_W_UD, ud);
  MV_ST(state, at + MV_BK_W_X, x);
  MV_ST(state, at + MV_BK_W_B, b);
  MV_ST(state, at + MV_BK_W_O, o);
  MV_ST(state, at + MV_BK_W_DD, dd);
  MV_ST(state, at + MV_BK_W_BEST, best);
  MV_ST(state, at + MV_BK_W_DMIN, dmin);
  MV_ST(state, at + MV_BK_W_DC, dc);
  MV_ST(state, at + MV_BK_W_HEAD, head);
  MV_ST(state, at + MV_BK_W_TAIL, tail);
  MV_ST(state, at + MV_BK_W_TIME, time);
  MV_ST(state, at + MV_BK_W_OHEAD, ohead);
  MV_ST(state, at + MV_BK_W_OCOUNT, ocount);
  MV_ST(state, at + MV_BK_W_FLOW, flow);
  return s;
}

/* An item takes the regions one after another from the counter after the regions' states (the host zeroes it
 * before each dispatch), so the items stay busy while regions are left whatever their sizes; p.budget steps
 * in all. A region's steps do not depend on the item that runs them. */
MV_INLINE void mv_bk_items(MvBufU32 resid, MvBufU32 term, MvBufU32 node, MvBufU32 next, MvBufU32 orphans,
                           MvBufU32 state, MvMinCutBkParams p) {
  mv_u32 regions = mv_bk_level_regions(p.regions_x, p.group) * mv_bk_level_regions(p.regions_y, p.group);
  mv_u32 left = p.budget;
  for (mv_u32 q = 0u; q < regions && left > 0u; ++q) {
    mv_u32 r = MV_ATOMIC_ADD(state, regions * MV_BK_STATE_WORDS, 1u);
    if (r >= regions) break;
    left -= mv_bk_run(resid, term, node, next, orphans, state, p, r, left);
  }
}

#endif /* MV_MIN_CUT_BK_H */

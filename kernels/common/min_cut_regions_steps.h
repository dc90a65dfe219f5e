/* The Boykov-Kolmogorov min-cut over regions (min_cut_regions.h): one region's state machine, a small step
 * per iteration of one loop (grow, find the bottleneck, push, adopt orphans), resumable from its state words. */
#ifndef MV_MIN_CUT_REGIONS_STEPS_H
#define MV_MIN_CUT_REGIONS_STEPS_H
#include "min_cut_regions_layout.h"

/* Runs region r of the level p.group says for `budget` steps at most from state[], stores the state back, and
 * returns the steps it took. */
MV_INLINE mv_u32 mv_bk_run(MvBufU32 resid, MvBufU32 term, MvBufU32 node, MvBufU32 next, MvBufU32 orphans,
                           MvBufU32 state, MvMinCutRegionsParams p, mv_u32 r, mv_u32 budget) {
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

#endif /* MV_MIN_CUT_REGIONS_STEPS_H */

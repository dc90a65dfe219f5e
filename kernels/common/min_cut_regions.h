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
 * (< 0) once the two have cancelled. The host keeps the total capacity below 2^31, so nothing overflows.
 * Parts: the memory layout, parameters and helpers in min_cut_regions_layout.h, a region's steps in
 * min_cut_regions_steps.h; here, how a work-item takes regions. */
#ifndef MV_MIN_CUT_REGIONS_H
#define MV_MIN_CUT_REGIONS_H
#include "min_cut_regions_steps.h"

/* An item takes the regions one after another from the counter after the regions' states (the host zeroes it
 * before each dispatch), so the items stay busy while regions are left whatever their sizes; p.budget steps
 * in all. A region's steps do not depend on the item that runs them. */
MV_INLINE void mv_bk_items(MvBufU32 resid, MvBufU32 term, MvBufU32 node, MvBufU32 next, MvBufU32 orphans,
                           MvBufU32 state, MvMinCutRegionsParams p) {
  mv_u32 regions = mv_bk_level_regions(p.regions_x, p.group) * mv_bk_level_regions(p.regions_y, p.group);
  mv_u32 left = p.budget;
  for (mv_u32 q = 0u; q < regions && left > 0u; ++q) {
    mv_u32 r = MV_ATOMIC_ADD(state, regions * MV_BK_STATE_WORDS, 1u);
    if (r >= regions) break;
    left -= mv_bk_run(resid, term, node, next, orphans, state, p, r, left);
  }
}

#endif /* MV_MIN_CUT_REGIONS_H */

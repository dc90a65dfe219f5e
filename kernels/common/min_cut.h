/* Exact min-cut of a pixel-grid graph (grid_graph.h) by tiled push-relabel, rounds driven by the host.
 *
 * The grid is cut into tiles of tile x tile pixels, coloured (tx & 1) + 2 (ty & 1). One dispatch runs the
 * tiles of one colour, one work-item per tile, each walking its tile in a fixed order. Tiles of one colour
 * never touch (not even diagonally; tiles are at least 2 pixels wide), so an item may read and write its
 * pixels' neighbours in the adjacent, idle tiles without atomics: every device runs the same operations in
 * the same order and keeps the same state, bit for bit.
 * A round is a global relabel (height = distance to the sink in the residual graph), computed afresh as a
 * breadth-first wave from the sink (min_cut_relabel.h: min_cut_seed, then min_cut_wave passes until still, which
 * the host queues in batches, a flag word a pass), then discharge passes:
 *   min_cut_active:   flag[1] is set when a pixel with excess can still reach the sink.
 *   min_cut_discharge: push-relabel sweeps over a tile: push to the sink, then along admissible edges
 *                     (height one above the neighbour's), then relabel (1 + the lowest residual neighbour);
 *                     tiles without movable excess are skipped.
 * Heights of pixels that cannot reach the sink are MV_MINCUT_INF: such pixels never receive flow again.
 * All values are 32-bit unsigned; the host keeps the total capacity below 2^31, so nothing overflows.
 * Loops are bounded by the tile size and the sweep count, which the host keeps within lavapipe's loop cap.
 * Parts: parameters, tiles and neighbours in min_cut_tiles.h, the global relabel in min_cut_relabel.h, the
 * discharge in min_cut_discharge.h. */
#ifndef MV_MIN_CUT_H
#define MV_MIN_CUT_H
#include "min_cut_relabel.h"
#include "min_cut_discharge.h"

#endif /* MV_MIN_CUT_H */

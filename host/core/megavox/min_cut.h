// megavox — exact min-cut of a pixel-grid graph on a device: Boykov-Kolmogorov over regions, merged while many
// regions are left, finished by push-relabel (kernels/common/min_cut_regions.h), or tiled push-relabel alone
// (kernels/common/min_cut.h).
//
// The answer is the same bytes on every device: the cut value (the maximum flow, exactly) and the canonical
// minimal source set (the pixels reachable from the source in the residual graph of a maximum flow, which is
// also Boykov-Kolmogorov's final source tree). The kernels solve the reversed graph (reversed_grid_graph), where
// that set is what can still reach the sink in the end: the sink's search tree (regions) or the pixels a last
// global relabel gives a height (push-relabel).
#pragma once
#include <cstdint>
#include <optional>
#include <string_view>

#include "megavox/device.h"
#include "megavox/grid_graph.h"

namespace mv {

// How the kernels find the cut: push-relabel over tiles (kernels/common/min_cut.h); Boykov-Kolmogorov over
// regions, merged 2 x 2 a level while a level keeps many regions, then push-relabel from the regions' flow for
// what crosses the last seams (kernels/common/min_cut_regions.h); or by the device (automatic): regions where each
// work-item is a CPU thread (a preferred work-group size of 1, not massively parallel: PoCL), push-relabel on
// SIMT devices (lavapipe) and massively parallel ones.
enum class MinCutSolver : uint8_t { push_relabel, regions, automatic };

// "push-relabel", "regions", "auto"; parse_min_cut_solver takes the same names (nullopt for others).
const char* min_cut_solver_name(MinCutSolver solver);
std::optional<MinCutSolver> parse_min_cut_solver(std::string_view name);
// The solver `automatic` stands for on this device; others as they are.
MinCutSolver resolve_min_cut_solver(const DeviceInfo& info, MinCutSolver solver);
// Work-items the device runs at once: compute units (at least 1) x preferred work-group size x 4. A dispatch with
// fewer leaves part of the device idle ("narrow").
uint64_t device_lanes(const DeviceInfo& info);

struct MinCutOptions {
  // push-relabel: tile side in pixels (2 to 32); one work-item per tile. 0: 16, halved on massively parallel
  // devices while a colour's tiles are fewer than the device's lanes (device_lanes).
  uint32_t tile = 0;
  // Push-relabel: passes over the four tile colours between two global relabels; 0: by size, one per 5 tiles
  // across the longer side, 4 to 12 (each pass is four dispatches: small grids lose more to them than they gain).
  uint32_t discharge_passes = 0;
  uint32_t sweeps = 3;             // push-relabel: sweeps over a tile per dispatch (fewer where loops are capped)
  MinCutSolver solver = MinCutSolver::automatic;
  // regions: regions x regions in the first level (then merged 2 x 2 a level); 0: from the device.
  uint32_t regions = 0;
  // regions: merging stops before a level of fewer regions than this, and push-relabel finishes from there (a
  // single region at the first level is solved alone); 0: from the device.
  uint32_t least_regions = 0;
};

struct MinCutStats {
  uint32_t rounds = 0;          // region dispatches plus push-relabel's global relabels (each followed by
                                // discharge passes but the last)
  MinCutSolver solver = MinCutSolver::automatic;  // the solver that ran (never automatic)
  uint32_t relabel_passes = 0;  // the global relabels' wave passes over the four colours, summed over the rounds
  bool warm = false;            // started from the flow of an earlier cut (MinCutFlow)
};

// The maximum flow a cut left on its graph's edges, to start the next cut of a graph with the same size and
// edge capacities from (GrabCut's iterations change only the terminal capacities). Where a pixel's new
// terminals cannot carry the flow its edges hold, the same amount is added to both of them, which adds it to
// every cut: the value is corrected and the canonical source set is unchanged, so a warm cut gives the cold
// cut's bytes. A graph whose edges differ, or whose total would pass kMaxGraphCapacity, starts cold.
struct MinCutFlow {
  uint32_t width = 0, height = 0, connectivity = 0;
  std::vector<uint32_t> edges;     // the graph's edge capacities
  std::vector<uint32_t> residual;  // the reversed graph's residual edge capacities at the end of the cut
};

// The push-relabel solver's global relabel alone (a breadth-first wave from the sink, kernels/common/
// min_cut_relabel.h), for its tests: each pixel's distance to the sink along edges with residual capacity
// (`residual[i * connectivity + d]`, pixel i's edge d, none leaving the grid; a pixel with sink capacity is one
// step away), UINT32_MAX where the sink cannot be reached. options.tile sets the tiles, as for the solver.
std::vector<uint32_t> min_cut_sink_distances(Device& dev, uint32_t width, uint32_t height, uint32_t connectivity,
                                             const std::vector<uint32_t>& residual, const std::vector<uint32_t>& sink,
                                             const MinCutOptions& options = {});

// Throws mv::Error on an invalid graph (validate_grid_graph) or when the device memory cannot hold it.
// With `flow`, starts from the flow it holds where it fits g, and leaves g's flow in it.
MinCut min_cut(Device& dev, const GridGraph& g, const MinCutOptions& options = {}, MinCutStats* stats = nullptr,
               MinCutFlow* flow = nullptr);

}  // namespace mv

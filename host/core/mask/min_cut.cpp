// The host side of the tiled push-relabel min-cut: uploads the reversed graph's residual capacities, then
// alternates global relabels (invalidation passes, then relaxation passes, each until nothing changes) and
// discharge passes until no pixel with excess can reach the sink, and reads the cut off the last heights.
#include "megavox/min_cut.h"

#include <algorithm>
#include <functional>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "common/min_cut.h"
#include "megavox/error.h"
#include "min_cut_regions.h"
#include "reversed_edge.h"

namespace mv {

namespace {

struct TilePlan {
  MvMinCutParams base{};
  uint32_t tiles_of[4] = {};  // tiles of each colour
  uint32_t local = 1;
};

// Loops are summed per invocation under a loop cap: a discharge sweep runs each pixel's edge loop up to
// MV_MINCUT_ATTEMPTS times (and the attempt loop), a relabel sweep a loop-free step per pixel (counted as one
// edge loop, so its sweeps stay four times the discharge's default).
uint32_t capped_sweeps(const DeviceInfo& info, uint32_t tile, uint64_t per_pixel, uint32_t sweeps) {
  if (info.max_loop_iterations == 0) return sweeps;
  return static_cast<uint32_t>(
      std::clamp<uint64_t>(info.max_loop_iterations / (uint64_t{tile} * tile * per_pixel), 1, sweeps));
}

// Tiles of one colour across a grid.
uint64_t colour_tiles(const GridGraph& g, uint32_t tile) {
  return uint64_t{(g.width + 2 * tile - 1) / (2 * tile)} * ((g.height + 2 * tile - 1) / (2 * tile));
}

TilePlan plan_tiles(const Device& dev, const GridGraph& g, const MinCutOptions& o) {
  const DeviceInfo& info = dev.info();
  uint32_t tile = std::clamp<uint32_t>(o.tile == 0 ? 16 : o.tile, 2, MV_MINCUT_MAX_TILE);
  // A massively parallel device wants a work-item per lane in every colour's dispatch.
  if (o.tile == 0 && info.massively_parallel)
    while (tile > 2 && colour_tiles(g, tile) < device_lanes(info)) tile /= 2;
  const uint64_t per_pixel = uint64_t{g.connectivity} * (MV_MINCUT_ATTEMPTS + 1);
  while (info.max_loop_iterations != 0 && tile > 2 && uint64_t{tile} * tile * per_pixel > info.max_loop_iterations)
    tile /= 2;
  const uint32_t sweeps = capped_sweeps(info, tile, per_pixel, std::max<uint32_t>(o.sweeps, 1));
  TilePlan plan;
  MvMinCutParams& p = plan.base;
  p.width = g.width;
  p.height = g.height;
  p.conn = g.connectivity;
  p.tile = tile;
  p.tiles_x = (g.width + tile - 1) / tile;
  p.tiles_y = (g.height + tile - 1) / tile;
  p.sweeps = sweeps;
  for (uint32_t c = 0; c < 4; ++c) {
    const uint32_t across = (p.tiles_x + 1 - (c & 1)) / 2, down = (p.tiles_y + 1 - (c >> 1)) / 2;
    plan.tiles_of[c] = across * down;
  }
  plan.local = std::max<uint32_t>(info.preferred_work_group_size, 1);
  return plan;
}

// One dispatch per colour (split where the group count passes the device's limit), a barrier after each.
void run_colours(Device& dev, Kernel& k, const TilePlan& plan, std::initializer_list<const Buffer*> buffers) {
  const uint32_t max_groups = std::max<uint32_t>(dev.info().max_groups, 1);
  for (uint32_t c = 0; c < 4; ++c) {
    MvMinCutParams p = plan.base;
    p.color = c;
    p.color_tiles_x = (p.tiles_x + 1 - (c & 1)) / 2;
    if (p.color_tiles_x == 0 || plan.tiles_of[c] == 0) continue;
    for (uint32_t first = 0; first < plan.tiles_of[c];) {
      const uint32_t groups = std::min<uint32_t>((plan.tiles_of[c] - first + plan.local - 1) / plan.local, max_groups);
      p.first_tile = first;
      dev.dispatch(k, groups, plan.local, buffers, p);
      first += groups * plan.local;
    }
    dev.barrier();
  }
}

// Whether an earlier cut's flow fits g (same size and edges, and the total after the terminals grow stays under
// kMaxGraphCapacity): then it is where this cut starts, and the terminals grow where the edges carry more out of
// a pixel than its source brings (excess). Returns the amount added to every cut. `total` is g's total capacity.
// The flow's words stay in flow->residual, read in place (no copy of the graph's edges is made for it).
uint64_t start_edges(const GridGraph& g, uint64_t total, const MinCutFlow* flow, std::vector<uint32_t>& excess,
                     std::vector<uint32_t>& sink, bool& warm) {
  const uint64_t n = uint64_t{g.width} * g.height;
  const uint32_t conn = g.connectivity;
  warm = flow && flow->width == g.width && flow->height == g.height && flow->connectivity == conn &&
         flow->edges == g.edges && flow->residual.size() == n * conn;
  if (!warm) return 0;
  const uint32_t* left = flow->residual.data();
  auto net_out = [&](uint64_t i) {  // the flow out of pixel i along the reversed graph's edges
    const uint32_t x = static_cast<uint32_t>(i % g.width), y = static_cast<uint32_t>(i / g.width);
    int64_t out = 0;
    for (uint32_t d = 0; d < conn; ++d) out += int64_t{reversed_edge(g, x, y, d)} - left[i * conn + d];
    return out;
  };
  // Integer sums: the same whatever the split between threads.
  const tbb::blocked_range<uint64_t> pixels(0, n, 4096);
  const uint64_t added = tbb::parallel_reduce(
      pixels, uint64_t{0},
      [&](const tbb::blocked_range<uint64_t>& r, uint64_t sum) {
        for (uint64_t i = r.begin(); i < r.end(); ++i) sum += uint64_t(std::max<int64_t>(net_out(i) - excess[i], 0));
        return sum;
      },
      std::plus<uint64_t>());
  if (total + 2 * added > kMaxGraphCapacity) {
    warm = false;
    return 0;
  }
  tbb::parallel_for(pixels, [&](const tbb::blocked_range<uint64_t>& r) {
    for (uint64_t i = r.begin(); i < r.end(); ++i) {
      const int64_t rest = int64_t{excess[i]} - net_out(i);
      if (rest < 0) sink[i] += static_cast<uint32_t>(-rest);
      excess[i] = static_cast<uint32_t>(std::max<int64_t>(rest, 0));
    }
  });
  return added;
}

// Tiled push-relabel on the reversed graph (kernels/common/min_cut.h), from the residual edges in rb and the
// pixels' excess and sink capacities: the flow that reached the sink, and in `reaches` the pixels that can
// still reach it (the canonical source set of the graph before its reversal).
uint64_t push_relabel(Device& dev, const GridGraph& g, const MinCutOptions& options, Buffer& rb,
                      const std::vector<uint32_t>& excess, std::vector<uint32_t>& sink, std::vector<uint8_t>& reaches,
                      MinCutStats& st) {
  const uint64_t n = uint64_t{g.width} * g.height;
  uint64_t sink_before = 0;
  for (uint64_t i = 0; i < n; ++i) sink_before += sink[i];
  Buffer eb = dev.alloc(n * 4, "min-cut excess");
  Buffer hb = dev.alloc(n * 4, "min-cut heights");
  Buffer sb = dev.alloc(n * 4, "min-cut sink capacities");
  // flags: [1] active pixels left; [2, 2 + kMaxBatch) one word per relabel pass of a batch.
  constexpr uint32_t kMaxBatch = 16;
  Buffer fb = dev.alloc((2 + kMaxBatch) * 4, "min-cut flags");
  const TilePlan plan = plan_tiles(dev, g, options);
  const uint64_t tiles = uint64_t{plan.base.tiles_x} * plan.base.tiles_y;
  Buffer tb = dev.alloc(tiles * 4, "min-cut tile stamps");
  Buffer ab = dev.alloc(tiles * 4, "min-cut active tiles");
  Buffer ub = dev.alloc(tiles * 4, "min-cut touched tiles");
  dev.fill(hb, MV_MINCUT_INF, n * 4);  // no pixel is known to reach the sink: the first relax finds them all
  dev.fill(tb, 0, tiles * 4);
  dev.fill(ab, 1, tiles * 4);  // every tile may hold excess at first
  dev.fill(ub, 1, tiles * 4);  // and is relaxed in the first round
  dev.upload(eb, excess.data(), n * 4);
  dev.upload(sb, sink.data(), n * 4);

  TilePlan still_plan = plan;
  still_plan.base.sweeps =
      capped_sweeps(dev.info(), plan.base.tile, g.connectivity, 4 * std::max<uint32_t>(options.sweeps, 1));
  Kernel& invalidate = dev.kernel(KernelId::min_cut_invalidate);
  Kernel& relax = dev.kernel(KernelId::min_cut_relax);
  Kernel& active = dev.kernel(KernelId::min_cut_active);
  Kernel& discharge = dev.kernel(KernelId::min_cut_discharge);
  uint32_t flags[2 + kMaxBatch] = {};
  MvMinCutParams& sp = still_plan.base;
  // One step of a global relabel (min_cut_invalidate or min_cut_relax), pass after pass until nothing changes:
  // first the touched tiles, then the tiles around each change of the pass before. Passes go in batches read
  // back at once, 2, 4, ... 16 a batch, so a relabel of P passes waits on the device about log P times, not P.
  auto settle = [&](Kernel& k) {
    sp.from_touched = 1;
    for (uint32_t batch = 1, still = 0; !still; batch = std::min(2 * batch, kMaxBatch)) {
      dev.fill(fb, 0, (2 + kMaxBatch) * 4);
      dev.barrier();
      for (uint32_t j = 0; j < batch; ++j, sp.from_touched = 0) {
        ++sp.stamp_now;
        sp.flag_word = 2 + j;
        run_colours(dev, k, still_plan, {&hb, &sb, &rb, &fb, &tb, &ub});
        sp.stamp_since = sp.stamp_now;
      }
      dev.download(fb, flags, (2 + batch) * 4);
      for (uint32_t j = 0; j < batch && !still; ++j) {
        ++st.relabel_passes;
        still = flags[2 + j] == 0;
      }
    }
  };
  // Each round's discharge moves excess closer to the sink or raises heights; push-relabel's bound on
  // relabels (2n per pixel) bounds the rounds, so the guard below only catches a broken device.
  const uint64_t max_rounds = 4 * n + 16;
  const uint32_t passes = options.discharge_passes != 0
                              ? options.discharge_passes
                              : std::clamp((std::max(plan.base.tiles_x, plan.base.tiles_y) + 4) / 5, 4u, 12u);
  for (uint64_t round = 1;; ++round) {
    if (round > max_rounds) throw Error("min-cut: no convergence after " + std::to_string(max_rounds) + " rounds");
    ++st.rounds;
    // The global relabel, from the heights the last round left: heights without support rise to unreachable,
    // then all fall to the distances.
    settle(invalidate);
    settle(relax);
    dev.fill(fb, 0, 8);
    dev.barrier();
    dev.dispatch(active, dev.groups_for(n, 64), 64, {&eb, &hb, &fb}, plan.base);
    dev.barrier();
    dev.download(fb, flags, 8);
    if (flags[1] == 0) break;
    for (uint32_t p = 0; p < passes; ++p)
      run_colours(dev, discharge, plan, {&eb, &hb, &sb, &rb, &ab, &ub});
  }
  std::vector<uint32_t> heights(n);
  dev.download(hb, heights.data(), n * 4);
  dev.download(sb, sink.data(), n * 4);
  uint64_t sink_after = 0;
  for (uint64_t i = 0; i < n; ++i) sink_after += sink[i];
  for (uint64_t i = 0; i < n; ++i) reaches[i] = heights[i] != MV_MINCUT_INF ? 1 : 0;
  return sink_before - sink_after;
}

// The region solver's shape on this device: the first level's regions across (and down), and the fewest regions a
// level may have. A region per lane at least (PoCL on 2 cores 4 x 4, lavapipe 8 x 8), and no level with fewer
// regions than lanes, so no region dispatch leaves the device idle: push-relabel finishes the seams.
struct RegionShape {
  uint32_t regions, least;
};
RegionShape region_shape(const DeviceInfo& info, const MinCutOptions& o) {
  // Where each work-item is a CPU thread running its items as a plain loop (a preferred work-group size of 1:
  // PoCL), 2 x 2 regions merged up to the whole grid are the fastest: the last level is one of the device's two
  // threads, and a thread runs BK's serial search as well as anything. Measured at ~1 MP 8-connected: 3.4x
  // Boost BK, against 0.9x for regions per lane finished by push-relabel (docs/decisions/min-cut-wide.md).
  const bool threads = info.preferred_work_group_size <= 1 && !info.massively_parallel;
  const uint64_t lanes = device_lanes(info);
  uint32_t regions = 2;
  while (!threads && uint64_t{regions} * regions < lanes && regions < 1024) regions *= 2;
  RegionShape s{o.regions != 0 ? o.regions : regions, o.least_regions};
  if (s.least == 0) s.least = threads ? 1 : static_cast<uint32_t>(std::min<uint64_t>(lanes, 1u << 20));
  return s;
}

}  // namespace

const char* min_cut_solver_name(MinCutSolver solver) {
  switch (solver) {
    case MinCutSolver::push_relabel: return "push-relabel";
    case MinCutSolver::regions: return "regions";
    case MinCutSolver::automatic: break;
  }
  return "auto";
}

std::optional<MinCutSolver> parse_min_cut_solver(std::string_view name) {
  for (MinCutSolver s : {MinCutSolver::push_relabel, MinCutSolver::regions, MinCutSolver::automatic})
    if (name == min_cut_solver_name(s)) return s;
  return std::nullopt;
}

MinCutSolver resolve_min_cut_solver(const DeviceInfo& info, MinCutSolver solver) {
  if (solver != MinCutSolver::automatic) return solver;
  return info.massively_parallel ? MinCutSolver::push_relabel : MinCutSolver::regions;
}

uint64_t device_lanes(const DeviceInfo& info) {
  return uint64_t{std::max<uint32_t>(info.compute_units, 1)} * std::max<uint32_t>(info.preferred_work_group_size, 1) * 4;
}

MinCut min_cut(Device& dev, const GridGraph& g, const MinCutOptions& options, MinCutStats* stats,
               MinCutFlow* flow) {
  const uint64_t total = validate_grid_graph(g);
  const uint64_t n = uint64_t{g.width} * g.height;
  // The reversed graph: source and sink swapped, every edge turned around.
  // Flow through a pixel's two terminal edges cancels first: what is left is excess or sink capacity.
  uint64_t value = 0;
  std::vector<uint32_t> excess(n), sink(n);
  for (uint64_t i = 0; i < n; ++i) {
    const uint32_t m = std::min(g.source[i], g.sink[i]);
    value += m;
    excess[i] = g.sink[i] - m;
    sink[i] = g.source[i] - m;
  }
  MinCutStats st;
  const uint64_t added = start_edges(g, total, flow, excess, sink, st.warm);
  // The residual edges: the earlier flow's, or the reversed graph's capacities (a zero flow).
  std::vector<uint32_t> capacities;
  if (!st.warm) capacities = reversed_edges(g);
  const std::vector<uint32_t>& residual = st.warm ? flow->residual : capacities;
  Buffer rb = dev.alloc(n * 4 * g.connectivity, "min-cut residual capacities");
  dev.upload(rb, residual.data(), n * 4 * g.connectivity);
  MinCut cut;
  cut.source_side.resize(n);
  // Both solvers cut the reversed graph: what can reach its sink is the source set before the reversal.
  st.solver = resolve_min_cut_solver(dev.info(), options.solver);
  uint64_t into_sink = 0;
  bool finished = false;
  if (st.solver == MinCutSolver::regions) {
    const RegionShape shape = region_shape(dev.info(), options);
    into_sink = mask::min_cut_regions(dev, g, shape.regions, shape.least, rb, excess, sink, cut.source_side, st, finished);
  }
  if (!finished) into_sink += push_relabel(dev, g, options, rb, excess, sink, cut.source_side, st);
  cut.value = value + into_sink - added;
  if (flow) {
    flow->width = g.width;
    flow->height = g.height;
    flow->connectivity = g.connectivity;
    if (!st.warm) {  // a warm start had the edges, and keeps its words
      flow->edges = g.edges;
      flow->residual.swap(capacities);
    }
    dev.download(rb, flow->residual.data(), n * 4 * g.connectivity);
  }
  if (stats) *stats = st;
  return cut;
}

}  // namespace mv

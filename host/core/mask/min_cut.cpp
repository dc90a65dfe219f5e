// The host side of the tiled push-relabel min-cut: uploads the reversed graph's residual capacities, then
// alternates global relabels (a breadth-first wave from the sink, pass after pass until it is still) and
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

// The wave relabel's tiles: as wide as the work list allows (32), so a wave crosses many levels a dispatch, but
// halved while a colour has fewer tiles than the device has lanes; on massively parallel devices the
// discharge's. A run visits up to 64 x its pixels (each visit loops over the pixel's neighbours), fewer under a
// loop cap. A tile set in the options is the wave's too.
TilePlan plan_wave(const Device& dev, const GridGraph& g, const MinCutOptions& o, const TilePlan& discharge) {
  const DeviceInfo& info = dev.info();
  TilePlan plan = discharge;
  MvMinCutParams& p = plan.base;
  p.tile = info.massively_parallel || o.tile != 0 ? discharge.base.tile : MV_MINCUT_MAX_TILE;
  if (o.tile == 0)
    while (p.tile > 2 && colour_tiles(g, p.tile) < device_lanes(info)) p.tile /= 2;
  const uint64_t per_pixel = uint64_t{g.connectivity} + 2;
  while (info.max_loop_iterations != 0 && p.tile > 2 && uint64_t{p.tile} * p.tile * per_pixel > info.max_loop_iterations)
    p.tile /= 2;
  p.tiles_x = (g.width + p.tile - 1) / p.tile;
  p.tiles_y = (g.height + p.tile - 1) / p.tile;
  p.sweeps = capped_sweeps(info, p.tile, per_pixel, 64);
  for (uint32_t c = 0; c < 4; ++c) {
    const uint32_t across = (p.tiles_x + 1 - (c & 1)) / 2, down = (p.tiles_y + 1 - (c >> 1)) / 2;
    plan.tiles_of[c] = across * down;
  }
  return plan;
}

// The flags of a relabel's wave passes: [1] active pixels left; [2, 2 + kMaxWaveBatch) one word per pass of a batch.
constexpr uint32_t kMaxWaveBatch = 16;

// The global relabel (kernels/common/min_cut_relabel.h): heights in hb become the distances to the sink in the
// residual graph rb, MV_MINCUT_INF where none. A seed, then wave passes until one changes no tile's border,
// queued in batches of 2, 4, ... 16 passes read back at once (a pass after a still one runs no tile), so a
// relabel of P passes waits on the device about log P times. `stamp` counts passes across relabels.
struct WaveRelabel {
  Device& dev;
  const GridGraph& g;
  TilePlan plan;
  Buffer tb, ub, fb;  // tile stamps, unfinished tiles, flags

  WaveRelabel(Device& d, const GridGraph& graph, const MinCutOptions& o, const TilePlan& discharge)
      : dev(d), g(graph), plan(plan_wave(d, graph, o, discharge)) {
    const uint64_t tiles = uint64_t{plan.base.tiles_x} * plan.base.tiles_y;
    tb = dev.alloc(tiles * 4, "min-cut wave stamps");
    ub = dev.alloc(tiles * 4, "min-cut wave unfinished tiles");
    fb = dev.alloc((2 + kMaxWaveBatch) * 4, "min-cut flags");
    dev.fill(tb, 0, tiles * 4);
    dev.fill(ub, 0, tiles * 4);
  }

  void run(Buffer& hb, Buffer& sb, Buffer& rb, MinCutStats& st) {
    const uint64_t n = uint64_t{g.width} * g.height;
    Kernel& seed = dev.kernel(KernelId::min_cut_seed);
    Kernel& wave = dev.kernel(KernelId::min_cut_wave);
    dev.dispatch(seed, dev.groups_for(n, 64), 64, {&hb, &sb}, plan.base);
    dev.barrier();
    MvMinCutParams& p = plan.base;
    p.first_pass = 1;
    uint32_t flags[2 + kMaxWaveBatch] = {};
    for (uint32_t batch = 1, still = 0; !still; batch = std::min(2 * batch, kMaxWaveBatch)) {
      dev.fill(fb, 0, (2 + kMaxWaveBatch) * 4);
      dev.barrier();
      for (uint32_t j = 0; j < batch; ++j, p.first_pass = 0) {
        ++p.stamp_now;
        p.flag_word = 2 + j;
        run_colours(dev, wave, plan, {&hb, &rb, &fb, &tb, &ub});
        p.stamp_since = p.stamp_now;
      }
      dev.download(fb, flags, (2 + batch) * 4);
      for (uint32_t j = 0; j < batch && !still; ++j) {
        ++st.relabel_passes;
        still = flags[2 + j] == 0;
      }
    }
  }
};

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
  const TilePlan plan = plan_tiles(dev, g, options);
  const uint64_t tiles = uint64_t{plan.base.tiles_x} * plan.base.tiles_y;
  Buffer ab = dev.alloc(tiles * 4, "min-cut active tiles");
  dev.fill(ab, 1, tiles * 4);  // every tile may hold excess at first
  dev.upload(eb, excess.data(), n * 4);
  dev.upload(sb, sink.data(), n * 4);
  WaveRelabel relabel(dev, g, options, plan);
  Kernel& active = dev.kernel(KernelId::min_cut_active);
  Kernel& discharge = dev.kernel(KernelId::min_cut_discharge);
  uint32_t flags[2] = {};
  // Each round's discharge moves excess closer to the sink or raises heights; push-relabel's bound on
  // relabels (2n per pixel) bounds the rounds, so the guard below only catches a broken device.
  const uint64_t max_rounds = 4 * n + 16;
  const uint32_t passes = options.discharge_passes != 0
                              ? options.discharge_passes
                              : std::clamp((std::max(plan.base.tiles_x, plan.base.tiles_y) + 4) / 5, 4u, 12u);
  for (uint64_t round = 1;; ++round) {
    if (round > max_rounds) throw Error("min-cut: no convergence after " + std::to_string(max_rounds) + " rounds");
    ++st.rounds;
    relabel.run(hb, sb, rb, st);
    dev.fill(relabel.fb, 0, 8);
    dev.barrier();
    dev.dispatch(active, dev.groups_for(n, 64), 64, {&eb, &hb, &relabel.fb}, plan.base);
    dev.barrier();
    dev.download(relabel.fb, flags, 8);
    if (flags[1] == 0) break;
    for (uint32_t p = 0; p < passes; ++p)
      run_colours(dev, discharge, plan, {&eb, &hb, &sb, &rb, &ab});
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
// level may have. Where each work-item is a CPU thread (PoCL), 2 x 2 regions merged up to the whole grid; else a
// region per lane at least (lavapipe 8 x 8), and no level with fewer regions than lanes: push-relabel finishes.
struct RegionShape {
  uint32_t regions, least;
};
RegionShape region_shape(const DeviceInfo& info, const MinCutOptions& o) {
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
  // Where each work-item is a CPU thread running its items as a plain loop (a preferred work-group size of 1:
  // PoCL), BK over 2 x 2 regions merged up to the whole grid is the fastest: the last level is one of the
  // device's threads, and a thread runs BK's serial search as well as anything. Elsewhere (SIMT lanes, GPUs)
  // push-relabel with the wave relabel: every dispatch is wide (docs/decisions/min-cut-wide.md).
  const bool threads = info.preferred_work_group_size <= 1 && !info.massively_parallel;
  return threads ? MinCutSolver::regions : MinCutSolver::push_relabel;
}

uint64_t device_lanes(const DeviceInfo& info) {
  return uint64_t{std::max<uint32_t>(info.compute_units, 1)} * std::max<uint32_t>(info.preferred_work_group_size, 1) * 4;
}

std::vector<uint32_t> min_cut_sink_distances(Device& dev, uint32_t width, uint32_t height, uint32_t connectivity,
                                             const std::vector<uint32_t>& residual, const std::vector<uint32_t>& sink,
                                             const MinCutOptions& options) {
  GridGraph g;
  g.width = width;
  g.height = height;
  g.connectivity = connectivity;
  const uint64_t n = uint64_t{width} * height;
  if (n == 0 || (connectivity != 4 && connectivity != 8) || residual.size() != n * connectivity || sink.size() != n)
    throw Error("min-cut distances: " + std::to_string(width) + " x " + std::to_string(height) + ", " +
                std::to_string(connectivity) + "-connected, does not match its " + std::to_string(residual.size()) +
                " edges and " + std::to_string(sink.size()) + " sink capacities");
  Buffer rb = dev.alloc(n * 4 * connectivity, "min-cut residual capacities");
  Buffer sb = dev.alloc(n * 4, "min-cut sink capacities");
  Buffer hb = dev.alloc(n * 4, "min-cut heights");
  dev.upload(rb, residual.data(), n * 4 * connectivity);
  dev.upload(sb, sink.data(), n * 4);
  MinCutStats st;
  WaveRelabel relabel(dev, g, options, plan_tiles(dev, g, options));
  relabel.run(hb, sb, rb, st);
  std::vector<uint32_t> heights(n);
  dev.download(hb, heights.data(), n * 4);
  return heights;
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

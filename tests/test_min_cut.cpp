// Every min-cut solver (region Boykov-Kolmogorov finished by push-relabel, tiled push-relabel, and the device's
// automatic choice) on every device against Boost.Graph's Boykov-Kolmogorov: the same cut value and the same
// source set (the canonical minimal one) on random 4- and 8-connected grids, extreme capacities, split grids,
// all-source and all-sink graphs and image-like graphs, cold and warm, plus the graph checks' messages.
#include <random>

#include "min_cut_reference.h"
#include "megavox/error.h"
#include "megavox/min_cut.h"
#include "test_support.h"

namespace mv::test {
namespace {

constexpr int kDx[8] = {1, -1, 0, 0, 1, -1, 1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, -1, 1};

bool inside(const GridGraph& g, uint32_t x, uint32_t y, uint32_t d) {
  const long nx = long{x} + kDx[d], ny = long{y} + kDy[d];
  return nx >= 0 && ny >= 0 && nx < long{g.width} && ny < long{g.height};
}

GridGraph empty_graph(uint32_t w, uint32_t h, uint32_t conn) {
  GridGraph g;
  g.width = w;
  g.height = h;
  g.connectivity = conn;
  g.source.assign(size_t{w} * h, 0);
  g.sink.assign(size_t{w} * h, 0);
  g.edges.assign(size_t{w} * h * conn, 0);
  return g;
}

// Random capacities below `cap`; a terminal edge on about `terminal_share` of the pixels, either side.
GridGraph random_graph(uint32_t w, uint32_t h, uint32_t conn, uint32_t cap, double terminal_share, uint64_t seed) {
  GridGraph g = empty_graph(w, h, conn);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<uint32_t> c(0, cap - 1);
  std::uniform_real_distribution<double> u(0, 1);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t{y} * w + x;
      if (u(rng) < terminal_share) g.source[i] = c(rng);
      if (u(rng) < terminal_share) g.sink[i] = c(rng);
      for (uint32_t d = 0; d < conn; ++d)
        if (inside(g, x, y, d)) g.edges[i * conn + d] = c(rng);
    }
  return g;
}

// An image-like graph: a bright disc on a dark, noisy background; data terms from the distance to either
// brightness, contrast-sensitive smoothness (GrabCut's shape, integer weights).
GridGraph disc_graph(uint32_t w, uint32_t h, uint32_t conn, uint64_t seed) {
  GridGraph g = empty_graph(w, h, conn);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, 40);
  std::vector<double> v(size_t{w} * h);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const double dx = x - 0.45 * w, dy = y - 0.55 * h;
      v[size_t{y} * w + x] = (dx * dx + dy * dy < 0.09 * w * h ? 180 : 70) + noise(rng);
    }
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t{y} * w + x;
      g.source[i] = static_cast<uint32_t>(std::abs(v[i] - 70));
      g.sink[i] = static_cast<uint32_t>(std::abs(v[i] - 180));
      for (uint32_t d = 0; d < conn; ++d) {
        if (!inside(g, x, y, d)) continue;
        const double diff = v[i] - v[size_t(long{y} + kDy[d]) * w + size_t(long{x} + kDx[d])];
        g.edges[i * conn + d] = static_cast<uint32_t>(50.0 * (d < 4 ? 1.0 : 0.7071) * std::exp(-diff * diff / 3200));
      }
    }
  return g;
}

constexpr MinCutSolver kSolvers[3] = {MinCutSolver::regions, MinCutSolver::push_relabel, MinCutSolver::automatic};

class MinCutTest : public ::testing::TestWithParam<DeviceInfo> {
 protected:
  Device& dev() { return shared_device(GetParam()); }

  // o first (its stats go to `stats`), then (unless `only`) every solver with o's other options.
  void expect_bk(const GridGraph& g, const std::string& what, const MinCutOptions& o = {},
                 MinCutStats* stats = nullptr, bool only = false) {
    const MinCut want = ref::bk_min_cut(g);
    for (int k = 0; k < (only ? 1 : 4); ++k) {
      MinCutOptions run = o;
      if (k > 0) run.solver = kSolvers[k - 1];
      SCOPED_TRACE(what + " (" + std::to_string(g.width) + " x " + std::to_string(g.height) + ", " +
                   std::to_string(g.connectivity) + "-connected, " + min_cut_solver_name(run.solver) + ")");
      const MinCut got = min_cut(dev(), g, run, k == 0 ? stats : nullptr);
      ASSERT_EQ(got.value, want.value);
      ASSERT_EQ(got.source_side.size(), want.source_side.size());
      size_t differ = 0;
      for (size_t i = 0; i < want.source_side.size(); ++i) differ += got.source_side[i] != want.source_side[i];
      ASSERT_EQ(differ, 0u) << "pixels on another side than Boost's source tree";
    }
  }
};

TEST_P(MinCutTest, RandomGridsMatchBoykovKolmogorov) {
  struct Size {
    uint32_t w, h;
  };
  uint64_t seed = 1;
  for (uint32_t conn : {4u, 8u})
    for (Size s : {Size{1, 1}, Size{1, 9}, Size{13, 1}, Size{2, 2}, Size{7, 5}, Size{33, 17}, Size{70, 65}})
      for (uint32_t cap : {1u, 2u, 10u, 1000u})
        for (double share : {0.1, 0.6}) expect_bk(random_graph(s.w, s.h, conn, cap, share, seed++), "random");
}

// Push-relabel: tiles of 2 and 3 pixels (every pixel near a tile seam), one discharge pass per relabel, many
// sweeps.
TEST_P(MinCutTest, SmallTilesAndOtherScheduleGiveTheSameCut) {
  for (uint32_t conn : {4u, 8u}) {
    const GridGraph g = random_graph(23, 19, conn, 100, 0.3, conn);
    expect_bk(g, "tile 2", {2, 1, 1});
    expect_bk(g, "tile 3", {3, 2, 5});
    expect_bk(g, "tile 64", {64, 8, 2});
  }
}

// Capacities at the edge of the 2^31 total; one edge holding nearly all of it; zero everywhere.
TEST_P(MinCutTest, ExtremeCapacities) {
  for (uint32_t conn : {4u, 8u}) {
    const uint32_t w = 20, h = 15;
    const uint64_t slots = uint64_t{w} * h * (conn + 2);
    expect_bk(random_graph(w, h, conn, static_cast<uint32_t>(kMaxGraphCapacity / slots), 1.0, 7 + conn), "near 2^31");
    GridGraph g = random_graph(w, h, conn, 5, 0.5, 9 + conn);
    g.source[0] = 0x7fff0000u;
    g.edges[0] = 0;  // the big source pixel reaches the rest through its other edges only
    expect_bk(g, "one huge source edge");
    g.sink[size_t{w} * h - 1] = 0x7f00u;
    expect_bk(g, "huge source, large sink");
    expect_bk(empty_graph(w, h, conn), "all zero");
  }
}

// A wall of zero capacity splits the grid into regions with their own terminals, one region has none.
TEST_P(MinCutTest, DisconnectedRegions) {
  for (uint32_t conn : {4u, 8u}) {
    GridGraph g = random_graph(40, 30, conn, 50, 0.4, 11 + conn);
    for (uint32_t y = 0; y < g.height; ++y)
      for (uint32_t x = 0; x < g.width; ++x)
        for (uint32_t d = 0; d < conn; ++d) {
          if (!inside(g, x, y, d)) continue;
          const long nx = long{x} + kDx[d], ny = long{y} + kDy[d];
          const bool crosses = (x < 17) != (nx < 17) || (y < 12) != (ny < 12);
          if (crosses) g.edges[(size_t{y} * g.width + x) * conn + d] = 0;
        }
    for (uint32_t y = 12; y < g.height; ++y)
      for (uint32_t x = 17; x < g.width; ++x) g.source[size_t{y} * g.width + x] = g.sink[size_t{y} * g.width + x] = 0;
    expect_bk(g, "four regions");
  }
}

TEST_P(MinCutTest, AllSourceAndAllSink) {
  for (uint32_t conn : {4u, 8u}) {
    GridGraph g = random_graph(37, 29, conn, 30, 0.0, 13 + conn);
    for (auto& c : g.source) c = 9;
    expect_bk(g, "all source");  // no flow; every pixel on the source side
    const MinCut cut = min_cut(dev(), g);
    EXPECT_EQ(cut.value, 0u);
    EXPECT_EQ(std::count(cut.source_side.begin(), cut.source_side.end(), 1), long(g.source.size()));
    g.sink = g.source;
    std::fill(g.source.begin(), g.source.end(), 0);
    expect_bk(g, "all sink");
    const MinCut none = min_cut(dev(), g);
    EXPECT_EQ(std::count(none.source_side.begin(), none.source_side.end(), 1), 0);
    g.source.assign(g.sink.size(), 10);  // both everywhere: everything cancels at the pixels
    expect_bk(g, "all both");
  }
}

TEST_P(MinCutTest, ImageLikeGraphs) {
  for (uint32_t conn : {4u, 8u}) expect_bk(disc_graph(150, 110, conn, 21 + conn), "disc");
}

// Each global relabel starts from the heights the last round left (invalidation, then relaxation): with
// little discharge between them, several rounds run, and each must leave exact distances for the cut.
TEST_P(MinCutTest, ManyIncrementalRelabelsGiveTheSameCut) {
  for (uint32_t conn : {4u, 8u}) {
    const GridGraph g = disc_graph(150, 110, conn, 31 + conn);
    MinCutStats st;
    MinCutOptions o{4, 1, 1};
    o.solver = MinCutSolver::push_relabel;
    expect_bk(g, "tile 4, one discharge pass of one sweep", o, &st);
    EXPECT_GE(st.rounds, 4u);
  }
}

// GrabCut's iterations: the same edges, new terminals. Each cut starting from the last one's flow gives BK's
// value and source set; terminals that cannot carry that flow grow on both sides (the value is corrected).
TEST_P(MinCutTest, WarmStartFromTheLastFlowGivesTheSameCut) {
  struct Run {
    MinCutSolver solver;
    uint32_t regions, least;
  };
  // Regions: the device's shape; merged to the whole grid (BK alone); 4 x 4 regions never merged.
  for (Run run : {Run{MinCutSolver::regions, 0, 0}, Run{MinCutSolver::regions, 2, 1}, Run{MinCutSolver::regions, 4, 64},
                  Run{MinCutSolver::push_relabel, 0, 0}, Run{MinCutSolver::automatic, 0, 0}})
  for (uint32_t conn : {4u, 8u}) {
    SCOPED_TRACE(std::string(min_cut_solver_name(run.solver)) + ", regions " + std::to_string(run.regions) +
                 ", least " + std::to_string(run.least));
    MinCutOptions o;
    o.solver = run.solver;
    o.regions = run.regions;
    o.least_regions = run.least;
    GridGraph g = disc_graph(120, 90, conn, 41 + conn);
    MinCutFlow flow;
    MinCutStats st;
    min_cut(dev(), g, o, &st, &flow);
    EXPECT_FALSE(st.warm);
    std::mt19937 rng(conn);
    for (int step = 0; step < 4; ++step) {
      for (size_t i = 0; i < g.source.size(); ++i) {  // move the terminals by up to +-40 %, zero some
        const uint32_t k = rng() % 100;
        if (k < 5) g.source[i] = 0;
        else if (k < 10) g.sink[i] = 0;
        else g.source[i] = static_cast<uint32_t>(g.source[i] * (0.6 + 0.8 * (rng() % 1000) / 1000.0));
      }
      const MinCut want = ref::bk_min_cut(g);
      const MinCut got = min_cut(dev(), g, o, &st, &flow);
      EXPECT_TRUE(st.warm);
      ASSERT_EQ(got.value, want.value) << "step " << step;
      ASSERT_TRUE(got.source_side == want.source_side) << "step " << step;
    }
    g.edges[size_t{g.width} * conn * 5 + 2] += 1;  // other edges: a cold start
    const MinCut got = min_cut(dev(), g, o, &st, &flow);
    EXPECT_FALSE(st.warm);
    EXPECT_EQ(got.value, ref::bk_min_cut(g).value);
  }
}

// Boykov-Kolmogorov over 1 (the whole grid at once), 3 x 3, 5 x 5 and 16 x 16 regions, merged 2 x 2 a level
// (uneven counts leave regions with one part, or two, to merge) up to the whole grid (least 1), down to 2 or 4
// regions, or not at all (least 1000), push-relabel finishing from the last level's flow.
TEST_P(MinCutTest, AnyRegionsGiveTheSameCut) {
  for (uint32_t conn : {4u, 8u})
    for (uint32_t regions : {1u, 3u, 5u, 16u})
      for (uint32_t least : {1u, 4u, 1000u}) {
        MinCutOptions o;
        o.solver = MinCutSolver::regions;
        o.regions = regions;
        o.least_regions = least;
        const std::string what = std::to_string(regions) + " regions, least " + std::to_string(least);
        MinCutStats st;
        expect_bk(disc_graph(150, 110, conn, 21 + conn), what, o, &st, true);
        EXPECT_EQ(st.solver, MinCutSolver::regions);
        expect_bk(random_graph(41, 37, conn, 100, 0.3, 50 + regions), what, o, nullptr, true);
      }
}

// What a massively parallel device gets: tiles small enough for a colour to fill it, a region per lane.
TEST_P(MinCutTest, WideShapesGiveTheSameCut) {
  for (uint32_t conn : {4u, 8u})
    for (uint32_t tile : {2u, 4u, 8u}) {
      MinCutOptions o;
      o.tile = tile;
      o.regions = 64 / tile;
      o.least_regions = o.regions * o.regions;
      for (MinCutSolver s : {MinCutSolver::push_relabel, MinCutSolver::regions}) {
        o.solver = s;
        expect_bk(disc_graph(150, 110, conn, 61 + conn), "tile " + std::to_string(tile), o, nullptr, true);
      }
    }
}

TEST_P(MinCutTest, SolverNamesAndTheAutomaticChoice) {
  for (MinCutSolver s : kSolvers) EXPECT_EQ(parse_min_cut_solver(min_cut_solver_name(s)), s);
  EXPECT_FALSE(parse_min_cut_solver("bk").has_value());
  DeviceInfo info = GetParam();
  info.massively_parallel = false;
  info.preferred_work_group_size = 1;  // a CPU thread a work-item
  EXPECT_EQ(resolve_min_cut_solver(info, MinCutSolver::automatic), MinCutSolver::regions);
  info.preferred_work_group_size = 8;  // SIMT lanes
  EXPECT_EQ(resolve_min_cut_solver(info, MinCutSolver::automatic), MinCutSolver::push_relabel);
  info.massively_parallel = true;
  EXPECT_EQ(resolve_min_cut_solver(info, MinCutSolver::automatic), MinCutSolver::push_relabel);
  EXPECT_EQ(resolve_min_cut_solver(info, MinCutSolver::regions), MinCutSolver::regions);
  MinCutStats st;
  min_cut(dev(), random_graph(9, 7, 8, 10, 0.5, 1), {}, &st);
  EXPECT_EQ(st.solver, resolve_min_cut_solver(dev().info(), MinCutSolver::automatic));
}

// The global relabel alone against a breadth-first search: random residual edges (some pixels cut off), a
// serpentine path through the whole grid (thousands of levels, every tile crossed many times), no sink at all,
// sink everywhere, one pixel and one line; every tile size, and the device's.
TEST_P(MinCutTest, WaveRelabelGivesTheDistancesToTheSink) {
  struct Case {
    std::string what;
    uint32_t w, h, conn;
    std::vector<uint32_t> residual, sink;
  };
  std::vector<Case> cases;
  for (uint32_t conn : {4u, 8u}) {
    for (double keep : {0.3, 0.6, 0.95}) {
      GridGraph g = random_graph(77, 53, conn, 4, 0.02, 90 + conn + uint64_t(keep * 10));
      std::mt19937 rng(conn);
      for (uint32_t& e : g.edges)
        if (rng() % 1000 >= keep * 1000) e = 0;
      cases.push_back({"random, " + std::to_string(keep) + " of the edges", g.width, g.height, conn, g.edges, g.sink});
    }
    GridGraph snake = empty_graph(70, 45, conn);  // row y runs toward x = 0 on even rows, then down at the end
    for (uint32_t y = 0; y < snake.height; ++y)
      for (uint32_t x = 0; x < snake.width; ++x) {
        const size_t i = size_t{y} * snake.width + x;
        const bool left = y % 2 == 0;
        const bool end = left ? x == 0 : x + 1 == snake.width;
        snake.edges[i * conn + (end ? 2u : left ? 1u : 0u)] = y + 1 == snake.height && end ? 0u : 1u;
      }
    snake.sink[snake.sink.size() - (snake.height % 2 ? snake.width : 1)] = 5;
    cases.push_back({"serpentine", snake.width, snake.height, conn, snake.edges, snake.sink});
    GridGraph none = random_graph(40, 30, conn, 9, 0.0, 7);
    cases.push_back({"no sink", none.width, none.height, conn, none.edges, none.sink});
    GridGraph all = random_graph(40, 30, conn, 9, 1.0, 8);
    for (uint32_t& c : all.sink) c = 1;
    cases.push_back({"sink everywhere", all.width, all.height, conn, all.edges, all.sink});
    cases.push_back({"one pixel", 1, 1, conn, std::vector<uint32_t>(conn, 0), {0}});
    GridGraph line = random_graph(200, 1, conn, 3, 0.01, 9);
    cases.push_back({"one line", line.width, line.height, conn, line.edges, line.sink});
  }
  for (const Case& c : cases)
    for (uint32_t tile : {0u, 2u, 5u, 16u, 32u}) {
      SCOPED_TRACE(c.what + ", " + std::to_string(c.conn) + "-connected, tile " + std::to_string(tile));
      MinCutOptions o;
      o.tile = tile;
      const std::vector<uint32_t> want = ref::sink_distances(c.w, c.h, c.conn, c.residual, c.sink);
      const std::vector<uint32_t> got = min_cut_sink_distances(dev(), c.w, c.h, c.conn, c.residual, c.sink, o);
      ASSERT_EQ(got.size(), want.size());
      size_t differ = 0;
      for (size_t i = 0; i < want.size(); ++i) differ += got[i] != want[i];
      ASSERT_EQ(differ, 0u);
    }
  EXPECT_THROW(min_cut_sink_distances(dev(), 3, 3, 4, std::vector<uint32_t>(35), std::vector<uint32_t>(9)), Error);
}

MV_INSTANTIATE_ON_ALL_DEVICES(MinCutTest);

TEST(GridGraph, BadGraphsAreRefusedWithReasons) {
  GridGraph g = empty_graph(4, 3, 8);
  EXPECT_EQ(error_message([&] { validate_grid_graph(g); }), "");
  GridGraph bad = g;
  bad.connectivity = 6;
  EXPECT_NE(error_message([&] { validate_grid_graph(bad); }).find("connectivity 6"), std::string::npos);
  bad = g;
  bad.sink.pop_back();
  EXPECT_NE(error_message([&] { validate_grid_graph(bad); }).find("do not match"), std::string::npos);
  bad = g;
  bad.edges[1] = 3;  // pixel (0, 0) toward -x
  EXPECT_NE(error_message([&] { validate_grid_graph(bad); }).find("leaves the grid"), std::string::npos);
  bad = g;
  bad.source[0] = 0x7fffffffu;
  bad.sink[1] = 1;
  EXPECT_NE(error_message([&] { validate_grid_graph(bad); }).find("2^31"), std::string::npos);
  bad = g;
  bad.width = 0;
  EXPECT_NE(error_message([&] { validate_grid_graph(bad); }).find("empty"), std::string::npos);
}

TEST(GridGraph, ReversalSwapsTerminalsAndEdges) {
  GridGraph g = random_graph(9, 7, 8, 100, 0.5, 3);
  GridGraph r = reversed_grid_graph(g);
  EXPECT_EQ(r.source, g.sink);
  EXPECT_EQ(r.sink, g.source);
  EXPECT_EQ(reversed_grid_graph(r).edges, g.edges);
  const MinCut a = ref::bk_min_cut(g), b = ref::bk_min_cut(r);
  EXPECT_EQ(a.value, b.value);
}

}  // namespace
}  // namespace mv::test

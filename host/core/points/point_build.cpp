#include "megavox/point_build.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "huge_pages.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "timing.h"
#include "omicron.h"
#include "omicron_front.h"
#include "point_gather.h"
#include "point_kernels.h"

namespace mv {

namespace {

// The front's entries as the leaves of a flat hierarchy, in front order; point i of node order is sorted point
// order[i].
void front_nodes(const points::OmicronFront& front, const points::OmicronBuilder& builder, std::vector<PointNode>& nodes,
                 std::vector<uint64_t>& order, std::vector<uint32_t>& roots) {
  for (const points::FrontEntry& e : front.entries()) {
    const points::LodNode& src = builder.level(e.level)[e.at];
    PointNode node;
    node.code = (uint64_t{1} << (3 * e.level)) | src.prefix;
    node.level = static_cast<uint8_t>(e.level);
    node.subtree_points = src.points;
    node.first_point = order.size();
    front.append_points(e, order);
    node.point_count = static_cast<uint32_t>(order.size() - node.first_point);
    roots.push_back(static_cast<uint32_t>(nodes.size()));
    nodes.push_back(node);
  }
}

}  // namespace

uint32_t point_depth_for(uint64_t points, uint32_t max_node_points) {
  const double ratio = static_cast<double>(points) / std::max<uint32_t>(1, max_node_points);
  const int level = ratio <= 1 ? 0 : static_cast<int>(std::ceil(std::log(ratio) / std::log(4.0)));
  return static_cast<uint32_t>(std::clamp(level + 2, 1, 21));
}

PointHierarchy build_point_hierarchy(Device& dev, PointColumns&& points, const PointCloudInfo& info,
                                     const PointBuildOptions& options, PointBuildReport* report,
                                     const std::function<void(const PointBuildProgress&)>& progress) {
  PointBuildReport local_report;
  PointBuildReport& rep = report ? *report : local_report;
  const uint64_t n = points.size();
  if (n == 0) throw Error("points: the cloud has no points");
  if (options.depth > 21) throw CodedError(ErrorCode::invalid_argument, "points: depth " + std::to_string(options.depth) + " is over 21, the deepest level 63-bit Morton codes hold", setting_depth);
  if (options.max_node_points == 0) throw CodedError(ErrorCode::invalid_argument, "points: the node point limit must be at least 1", setting_max_node_points);
  if (options.grid_bits < 1 || options.grid_bits > 10) throw Error("points: the node grid must have 1-10 bits per axis");

  auto t0 = std::chrono::steady_clock::now();
  const points::PointCube cube = points::cube_on_device(dev, points.xyz);

  // The builder consumes the sorted codes a prefix at a time, as the sort finishes them: its cut advances as a
  // stream's would.
  points::OmicronRule rule;
  rule.depth = options.depth ? options.depth : point_depth_for(n, options.max_node_points);
  rule.max_node_points = options.max_node_points;
  rule.grid_bits = options.grid_bits;
  auto owned_builder = std::make_unique<points::OmicronBuilder>(dev, rule);
  points::OmicronBuilder& builder = *owned_builder;
  // The partials' grid, for the front's rule and the checkpoints.
  PointHierarchy grid;
  grid.source = info;
  for (int a = 0; a < 3; ++a) grid.cube_min[a] = cube.min[a];
  grid.shift = cube.shift;
  grid.grid_bits = rule.grid_bits;
  grid.depth = rule.depth;
  grid.points_in = n;
  std::unique_ptr<points::OmicronFront> front;
  points::OmicronFront::FineEnough fine;
  if (options.front_fine_enough) {
    front = std::make_unique<points::OmicronFront>(builder);
    fine = [&](uint32_t level, uint64_t prefix) { return options.front_fine_enough(grid, level, prefix); };
  }
  std::span<const uint64_t> codes;
  std::span<const uint32_t> index;
  const uint64_t step = std::max<uint64_t>(1, options.prefix_points);
  uint64_t next_checkpoint = options.checkpoint_points;
  uint64_t consumed = 0;       // sorted points handed to the builder
  double build_in_sort = 0;    // seconds the builder took while the sort went on
  auto consume = [&](uint64_t available) {
    const auto tb = std::chrono::steady_clock::now();
    while (consumed < available) {
      const uint64_t end = std::min(consumed + step, available);
      builder.concatenate(codes.first(end), end == n);
      consumed = end;
      ++rep.steps;
      if (front) front->update(fine);
      if (options.on_checkpoint && end < n && builder.formed() >= next_checkpoint) {
        while (next_checkpoint <= builder.formed()) next_checkpoint += std::max<uint64_t>(1, options.checkpoint_points);
        PointHierarchy partial = grid;
        std::vector<uint64_t> order;
        std::vector<uint32_t> roots;
        if (front) {
          front_nodes(*front, builder, partial.nodes, order, roots);
          for (uint32_t l = 0; l <= rule.depth; ++l) {
            const auto& list = builder.level(l);
            partial.nodes_per_level.push_back(static_cast<uint64_t>(
                std::count_if(list.begin(), list.end(), [](const points::LodNode& x) { return !x.absorbed; })));
          }
        } else {
          builder.snapshot(partial.nodes, order, roots);
        }
        for (uint64_t& q : order) q = index[q];
        partial.points = points::gather_columns(points, order, info.extra_bytes);
        partial.points_kept = builder.formed();
        options.on_checkpoint(partial, roots);
      }
      if (progress) {
        PointBuildProgress p;
        p.points_formed = builder.formed();
        p.points_total = n;
        for (uint32_t l = 0; l <= rule.depth; ++l) p.nodes += builder.level(l).size();
        progress(p);
      }
    }
    build_in_sort += seconds_since(tb);
  };

  // Sorted (code, index) pairs: read in place on the device where it is host memory, else host vectors.
  points::SortedCodes in_place;
  std::vector<uint64_t> host_codes;
  std::vector<uint32_t> host_index;
  const auto on_prefix = [&](std::span<const uint64_t> c, std::span<const uint32_t> i, uint64_t end) {
    codes = c;
    index = i;
    consume(end);
  };
  if (points::sorted_codes_in_place(dev, points.xyz, cube, in_place, on_prefix, options.sort_ranges)) {
    rep.codes_seconds = seconds_since(t0) - in_place.sort_seconds;
    rep.sort_seconds = in_place.sort_seconds - build_in_sort;  // the builder's share of that time is its own
    rep.sort = in_place.sort;
    codes = in_place.codes;
    index = in_place.index;
  } else {
    points::point_codes(dev, points.xyz, cube, host_codes, host_index);
    rep.codes_seconds = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    rep.sort = radix_sort(dev, host_codes, &host_index);
    rep.sort_seconds = seconds_since(t0);
    codes = host_codes;
    index = host_index;
    consume(n);
  }
  t0 = std::chrono::steady_clock::now();
  PointHierarchy h;
  std::vector<points::NodePoints> sources;
  builder.assemble(h.nodes, sources, h.nodes_per_level);
  rep.build_seconds = build_in_sort + seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  // What the gathers no longer need goes back first, the device's storage included (host memory on a CPU device;
  // trim() frees it once no buffer lives there), so that their fresh memory lands on pages this process has just
  // given back (a first touch of new memory is the slow part of it).
  front.reset();
  const std::vector<uint64_t> reps = builder.take_reps();
  owned_builder.reset();
  codes = {};
  host_codes = {};
  in_place.keys = Buffer();
  if (!in_place.values.empty()) {  // the index leaves the device's storage (a third of it), so that all of it goes back
    reserve_huge(host_index, n);
    host_index.assign(index.begin(), index.end());
    index = host_index;
    in_place.values = Buffer();
  }
  dev.trim();

  if (computes_in_host_memory(dev)) {
    // Where the device's memory is the host's, the columns are already there: a kernel would be this loop plus
    // copies up and down (2-3x slower). Into sorted order first (one random read per input point), then into node
    // order, where a leaf is a block copy and representatives ascend within their node (at 100M points 1.5x
    // faster than one gather through the composed index).
    PointColumns sorted = points::gather_columns(points, std::span<const uint32_t>(index), info.extra_bytes);
    points = PointColumns();
    h.points = points::gather_node_points(sorted, sources, reps, info.extra_bytes);
  } else {
    // Elsewhere each column goes up once and straight into node order, through the composed index.
    h.points = points::gather_node_points(dev, std::move(points), index, sources, reps, info.extra_bytes);
  }
  index = {};
  host_index = {};
  rep.gather_seconds = seconds_since(t0);

  points::set_grid_and_counts(h, info, cube, rule.grid_bits, n);
  return h;
}

}  // namespace mv

// `megavox points build`: read the cloud, sort and build on the device, write the result.
#include <chrono>

#include <algorithm>
#include <filesystem>

#include "io/memory_points.h"
#include "io/output_path.h"
#include "io/point_source.h"
#include "io/temp_file.h"
#include "points/omicron.h"
#include "points/point_ranks.h"
#include "points/point_ranks_tiles.h"
#include "points/point_runs.h"
#include "io/crs_frame.h"
#include "io/tiles3d_writer.h"
#include "megavox/build.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "megavox/point_build.h"
#include "option_words.h"
#include "timing.h"

namespace mv {

namespace {

// Host bytes per point while building in core: the columns, the codes and indices with the sort's copies, the
// node-order list and the output columns.
uint64_t host_bytes_per_point(const PointCloudInfo& info) {
  uint64_t record = 12;
  if (info.attributes & kPointRgb) record += 6;
  if (info.attributes & kPointNormal) record += 12;
  if (info.attributes & kPointIntensity) record += 2;
  if (info.attributes & kPointExtra) record += info.extra_bytes;
  return 2 * record + 2 * (8 + 4) + 8 + 8;
}

}  // namespace

namespace {

// Every point of `src`, read from the file `path` (named when it holds none).
PointColumns read_all(io::PointSource& src, const std::string& path, const Progress& progress) {
  const uint64_t declared = src.info().points;
  PointColumns cloud;
  // The readers refuse counts their file cannot hold, so the declared count is safe to reserve.
  cloud.reserve_more(declared, src.info().attributes, src.info().extra_bytes);
  const size_t batch = size_t{1} << 20;
  while (src.next(cloud, batch))
    if (progress && declared) progress("read", std::min(1.0, double(cloud.size()) / double(declared)));
  if (cloud.size() == 0) throw Error(path + ": the cloud has no points");
  return cloud;
}

}  // namespace

PointColumns read_point_file(const std::string& path, PointCloudInfo& info, bool carry_extra_bytes,
                             const Progress& progress) {
  io::PointReadOptions ro;
  ro.carry_extra_bytes = carry_extra_bytes;
  std::unique_ptr<io::PointSource> src = io::open_points(path, ro);
  info = src->info();
  return read_all(*src, path, progress);
}

namespace {

// Host bytes per point of the out-of-core path: the codes and the node order in memory, the output columns.
uint64_t out_of_core_bytes_per_point(const PointCloudInfo& info) {
  return 8 + 8 * 3 / 2 + (host_bytes_per_point(info) - 56) / 2 * 3 / 2;
}

// Out of core: a pass for the bounds (the cube), a pass that sorts runs on the device into scratch files, then
// their merge, which the builder consumes prefix by prefix; the columns are gathered back from the merged file.
PointHierarchy build_out_of_core(Device& dev, const PointFileOptions& o, uint64_t memory, PointFileReport& r,
                                 std::unique_ptr<io::PointSource> first, const Progress& progress) {
  auto t0 = std::chrono::steady_clock::now();
  io::PointReadOptions ro;
  ro.carry_extra_bytes = o.carry_extra_bytes;
  ro.bounds = o.bounds;
  int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
  uint64_t n = 0;
  PointCloudInfo info;
  {
    std::unique_ptr<io::PointSource> src = std::move(first);
    info = src->info();
    PointColumns batch;
    while (src->next(batch, size_t{1} << 20)) {
      int64_t blo[3], bhi[3];
      if (batch.size()) points::point_bounds(dev, batch.xyz, blo, bhi);
      for (int a = 0; a < 3 && batch.size(); ++a) {
        lo[a] = std::min(lo[a], blo[a]);
        hi[a] = std::max(hi[a], bhi[a]);
      }
      n += batch.size();
      batch.clear();
      if (progress && info.points) progress("read", 0.5 * std::min(1.0, double(n) / double(info.points)));
    }
  }
  if (n == 0) throw Error(o.input + ": the cloud has no points");
  const points::PointCube cube = points::cube_of_bounds(lo, hi);
  const points::RecordLayout layout = points::record_layout(info);
  const uint64_t run_points =
      o.run_points ? o.run_points : std::max<uint64_t>(uint64_t{1} << 16, memory / (2 * uint64_t{layout.bytes} + 40));
  points::RunSorter sorter(dev, info, cube);
  {
    std::unique_ptr<io::PointSource> src = io::open_points(o.input, ro);
    PointColumns run;
    uint64_t seen = 0;
    while (src->next(run, static_cast<size_t>(std::min<uint64_t>(run_points - run.size(), uint64_t{1} << 20)))) {
      if (run.size() >= run_points) {
        seen += run.size();
        sorter.add_run(run);
        run.clear();
        if (progress) progress("read", 0.5 + 0.5 * double(seen) / double(n));
      }
    }
    sorter.add_run(run);
  }
  if (sorter.points() != n) throw Error(o.input + ": the file changed while it was read");
  r.read_seconds = seconds_since(t0);
  r.sort_runs = sorter.runs();

  t0 = std::chrono::steady_clock::now();
  points::OmicronRule rule;
  rule.depth = o.build.depth ? o.build.depth : point_depth_for(n, o.build.max_node_points);
  rule.max_node_points = o.build.max_node_points;
  rule.grid_bits = o.build.grid_bits;
  points::OmicronBuilder builder(dev, rule);
  std::vector<uint64_t> codes;
  codes.reserve(n);
  io::TempFile sorted("merging sorted points");
  uint64_t fed = 0;
  const uint64_t step = std::max<uint64_t>(1, o.build.prefix_points);
  sorter.merge(size_t{1} << 16, [&](const uint8_t* recs, size_t count) {
    sorted.write_at(recs, uint64_t{count} * layout.bytes, codes.size() * layout.bytes);
    for (size_t k = 0; k < count; ++k) codes.push_back(points::record_code(recs + uint64_t{k} * layout.bytes));
    if (codes.size() - fed >= step) {  // the builder takes the merged prefix while the merge goes on
      builder.concatenate(codes, false);
      fed = codes.size();
      if (progress) progress("build", double(fed) / double(n));
    }
  });
  builder.concatenate(codes, true);
  PointHierarchy h;
  std::vector<points::NodePoints> sources;
  builder.assemble(h.nodes, sources, h.nodes_per_level);
  std::vector<uint64_t> order;
  points::expand_order(sources, builder.reps(), order);
  codes = {};
  const uint64_t bytes = n * layout.bytes;
  const uint8_t* map = static_cast<const uint8_t*>(sorted.map(bytes));
  for (uint64_t q : order) points::unpack(layout, map + q * layout.bytes, h.points);
  io::TempFile::unmap(const_cast<uint8_t*>(map), bytes);
  r.sort_seconds = 0;  // the runs are sorted inside the read pass, the merge inside the build
  r.build_seconds = seconds_since(t0);
  r.build.steps = builder.stats().fixes;

  points::set_grid_and_counts(h, info, cube, rule.grid_bits, n);
  r.input_format = info.format;
  return h;
}

// Writes the hierarchy to the checked output and completes the report.
// `share`: over ranks, the other ranks' part in a tileset.
PointFileReport write_points_output(const PointFileOptions& o, const std::string& output, PointHierarchy&& h,
                                    PointFileReport& r, std::chrono::steady_clock::time_point start,
                                    const Progress& progress, const io::Tiles3dShare* share = nullptr,
                                    const PointsElsewhere* points_share = nullptr) {
  const auto t0 = std::chrono::steady_clock::now();
  if (progress) progress("write", 0);
  if (o.format == PointOutput::mvx) write_mvx_points(output, h, points_share ? *points_share : PointsElsewhere{});
  else io::write_3dtiles(output, h, points::tiles_options_of(o), share ? *share : io::Tiles3dShare{});
  r.write_seconds = seconds_since(t0);  // no report after the write: a cancel there would come too late

  r.points_in = h.points_in;
  r.points_kept = h.points_kept;
  r.points_dropped = h.points_dropped;
  r.nodes = h.nodes.size();
  r.stored_points = 0;  // h holds only its own nodes' points when other processes wrote theirs
  for (const PointNode& n : h.nodes) r.stored_points += n.point_count;
  r.depth = h.depth;
  r.nodes_per_level = h.nodes_per_level;
  r.total_seconds = seconds_since(start);
  r.points_per_second = r.total_seconds > 0 ? double(r.points_in) / r.total_seconds : 0;
  return r;
}

}  // namespace

std::string check_output(const PointFileOptions& o) {
  // The output holds every point kept: about half the input's bytes at least.
  std::error_code size_error;
  const uint64_t input_bytes = std::filesystem::file_size(o.input, size_error);
  const bool file = o.format != PointOutput::tiles3d;
  if (!o.crs.empty()) {  // a wrong --crs costs nothing
    try {
      io::check_crs(o.crs);
    } catch (const Error& e) {
      throw CodedError(ErrorCode::invalid_argument, e.what());
    }
  }
  return io::resolve_output({o.output, file ? io::OutputKind::kFile : io::OutputKind::kFolder, file ? "mvx" : "",
                             {o.arrays ? std::string() : o.input}, size_error ? 0 : input_bytes / 2, o.no_clobber});
}

PointFileReport build_points_file(Device& dev, const PointFileOptions& o, const Progress& progress) {
  const bool spread = o.ranks && o.ranks->size > 1 && !o.arrays;
  const bool writes = !spread || o.ranks->rank == 0;
  const std::string output = writes ? check_output(o) : std::string();
  const auto start = std::chrono::steady_clock::now();
  PointFileReport r;
  r.input = o.input;
  r.output = o.output;
  r.format = point_output_name(o.format);
  const uint64_t memory = o.memory ? o.memory : default_host_memory();

  PointHierarchy h;
  auto t0 = std::chrono::steady_clock::now();
  if (spread) {
    // Each rank holds its share of the points (cells dealt by count) until they are written.
    const auto fits = [&](const PointCloudInfo& info) {
      const uint64_t need = info.points * host_bytes_per_point(info) / uint64_t(o.ranks->size);
      if (need > memory)
        throw CodedError(ErrorCode::out_of_memory,
                         "points build over ranks: each rank holds its share of the " + std::to_string(info.points) +
                             " points, which needs about " + format_bytes(need) + ", over the host memory budget " +
                             format_bytes(memory) + "; run it over more ranks, or in one process, which builds out of core",
                         setting_host_memory);
    };
    io::Tiles3dShare tiles;
    PointsElsewhere points_share;
    h = points::build_over_ranks(dev, o, *o.ranks, r, progress, fits, &tiles, &points_share);
    if (!writes) {
      r.total_seconds = seconds_since(start);
      return r;
    }
    return write_points_output(o, output, std::move(h), r, start, progress, &tiles, &points_share);
  }
  io::PointReadOptions ro;
  ro.carry_extra_bytes = o.carry_extra_bytes;
  ro.bounds = o.bounds;
  std::unique_ptr<io::PointSource> src = o.arrays ? io::memory_points(*o.arrays, o.input) : io::open_points(o.input, ro);
  const PointCloudInfo info = src->info();
  r.input_format = info.format;
  const uint64_t need = info.points * host_bytes_per_point(info);
  if (!o.arrays && (need > memory || o.run_points)) {
    const uint64_t ooc = info.points * out_of_core_bytes_per_point(info);
    if (ooc > memory)
      throw CodedError(ErrorCode::out_of_memory,
                       "points build: " + std::to_string(info.points) + " points need about " + format_bytes(ooc) +
                           " of host memory even out of core (codes, node order and the output's columns), over the "
                           "host memory budget " + format_bytes(memory),
                       setting_host_memory);
    r.out_of_core = true;
    h = build_out_of_core(dev, o, memory, r, std::move(src), progress);
  } else {
    PointColumns cloud = read_all(*src, o.input, progress);
    src.reset();
    r.read_seconds = seconds_since(t0);
    if (progress) progress("read", 1);
    if (progress) progress("build", 0);
    h = build_point_hierarchy(dev, std::move(cloud), info, o.build, &r.build, [&](const PointBuildProgress& p) {
      if (progress) progress("build", double(p.points_formed) / double(p.points_total));
    });
    r.sort_seconds = r.build.codes_seconds + r.build.sort_seconds;
    r.build_seconds = r.build.build_seconds + r.build.gather_seconds;
    r.sort_runs = r.build.sort.runs;
  }

  return write_points_output(o, output, std::move(h), r, start, progress);
}

}  // namespace mv

// `megavox points build`: read the cloud, sort and build on the device, write the result.
#include <chrono>

#include "io/point_source.h"
#include "io/tiles3d_writer.h"
#include "megavox/build.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "megavox/point_build.h"

namespace mv {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

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

PointColumns read_point_file(const std::string& path, PointCloudInfo& info, bool carry_extra_bytes,
                             const Progress& progress) {
  io::PointReadOptions ro;
  ro.carry_extra_bytes = carry_extra_bytes;
  std::unique_ptr<io::PointSource> src = io::open_points(path, ro);
  info = src->info();
  PointColumns cloud;
  const size_t batch = size_t{1} << 20;
  while (src->next(cloud, batch))
    if (progress && info.points) progress("read", std::min(1.0, double(cloud.size()) / double(info.points)));
  return cloud;
}

PointFileReport build_points_file(Device& dev, const PointFileOptions& o, const Progress& progress) {
  if (o.format != "mvx" && o.format != "3dtiles")
    throw Error("points build: unknown --format '" + o.format + "' (use mvx or 3dtiles)");
  const auto start = std::chrono::steady_clock::now();
  PointFileReport r;
  r.input = o.input;
  r.output = o.output;
  r.format = o.format;
  const uint64_t memory = o.memory ? o.memory : default_host_memory();

  auto t0 = std::chrono::steady_clock::now();
  io::PointReadOptions ro;
  ro.carry_extra_bytes = o.carry_extra_bytes;
  std::unique_ptr<io::PointSource> src = io::open_points(o.input, ro);
  const PointCloudInfo info = src->info();
  r.input_format = info.format;
  const uint64_t need = info.points * host_bytes_per_point(info);
  if (need > memory)
    throw Error("points build: " + std::to_string(info.points) + " points need about " + format_bytes(need) +
                " of host memory to build in core, over --memory " + format_bytes(memory) +
                "; raise --memory (the out-of-core sort is not there yet)");
  PointColumns cloud;
  const size_t batch = size_t{1} << 20;
  while (src->next(cloud, batch))
    if (progress && info.points) progress("read", std::min(1.0, double(cloud.size()) / double(info.points)));
  src.reset();
  r.read_seconds = seconds_since(t0);
  if (progress) progress("read", 1);

  if (progress) progress("build", 0);
  PointHierarchy h = build_point_hierarchy(dev, std::move(cloud), info, o.build, &r.build,
                                           [&](const PointBuildProgress& p) {
                                             if (progress) progress("build", double(p.points_formed) / double(p.points_total));
                                           });
  r.sort_seconds = r.build.codes_seconds + r.build.sort_seconds;
  r.build_seconds = r.build.build_seconds + r.build.gather_seconds;

  t0 = std::chrono::steady_clock::now();
  if (progress) progress("write", 0);
  if (o.format == "mvx") write_mvx_points(o.output, h);
  else io::write_3dtiles(o.output, h);
  r.write_seconds = seconds_since(t0);
  if (progress) progress("write", 1);

  r.points_in = h.points_in;
  r.points_kept = h.points_kept;
  r.points_dropped = h.points_dropped;
  r.nodes = h.nodes.size();
  r.stored_points = h.points.size();
  r.depth = h.depth;
  r.nodes_per_level = h.nodes_per_level;
  r.total_seconds = seconds_since(start);
  r.points_per_second = r.total_seconds > 0 ? double(r.points_in) / r.total_seconds : 0;
  return r;
}

}  // namespace mv

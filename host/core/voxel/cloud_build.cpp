// `megavox build` of a point cloud: every point fills the voxel it falls in (the grid rules of meshes, in
// double precision), the voxels and their depth-first colours come from the device (voxelize_cloud), and the
// DAG from the voxels' codes, as for any other input.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "io/cloud_input.h"
#include "megavox/build.h"
#include "megavox/colour.h"
#include "megavox/error.h"
#include "option_words.h"
#include "voxel/build_plan.h"
#include "voxel/build_steps.h"

namespace mv {

namespace {

// Grid cells of the points inside the grid, with their colours: x = (p - origin) / voxel_size as meshes map
// vertices; voxel i holds [i, i + 1), the top face the last voxel. Placed around the cloud nothing is outside
// (round-off is clamped); an explicit cube drops the points outside it.
void cloud_cells(const io::CloudPoints& cloud, const GridTransform& g, bool clip, std::vector<uint32_t>& cells,
                 std::vector<uint32_t>& rgb) {
  const double n = g.resolution, inv = 1.0 / g.voxel_size;
  const size_t points = cloud.xyz.size() / 3;
  cells.reserve(points * 3);
  if (!cloud.rgb.empty()) rgb.reserve(points);
  for (size_t p = 0; p < points; ++p) {
    uint32_t c[3];
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      double x = (cloud.xyz[3 * p + a] - g.origin[a]) * inv;
      if (clip && !(x >= 0 && x <= n)) inside = false;
      x = std::clamp(x, 0.0, n);
      c[a] = static_cast<uint32_t>(std::min(std::floor(x), n - 1));
    }
    if (!inside) continue;
    cells.insert(cells.end(), c, c + 3);
    if (!cloud.rgb.empty()) rgb.push_back(cloud.rgb[p]);
  }
}

}  // namespace

void build_cloud(Device& dev, const BuildOptions& o, BuildReport& r, const std::function<void(const std::string&)>& lap,
                 const PlanListener& on_plan) {
  using Clock = std::chrono::steady_clock;
  const uint32_t resolution = o.resolution ? o.resolution : 1024;
  if (o.voxelize != Voxelizer::Rule::kConservative)
    throw CodedError(ErrorCode::invalid_argument,
                     o.input + ": --voxelize applies to meshes; a point fills the voxel it falls in", setting_voxelize);
  io::CloudPoints cloud = io::read_cloud(o.input, o.attributes != Attributes::none);
  if (o.attributes == Attributes::rgb && cloud.rgb.empty())
    throw CodedError(ErrorCode::invalid_argument, o.input + ": --attributes rgb, but the cloud has no colours",
                     setting_none);
  const bool clip = o.placement.origin == GridPlacement::Origin::kCube;
  const GridTransform grid = grid_for_bounds(cloud.bounds, resolution, o.placement);
  Bounds bounds = cloud.bounds;
  if (clip)
    for (int a = 0; a < 3; ++a) {
      bounds.lo[a] = std::max(bounds.lo[a], grid.origin[a]);
      bounds.hi[a] = std::min(bounds.hi[a], grid.origin[a] + grid.voxel_size * grid.resolution);
    }
  std::vector<uint32_t> cells, rgb;
  cloud_cells(cloud, grid, clip, cells, rgb);
  cloud = {};
  if (cells.empty()) throw CodedError(ErrorCode::input, o.input + ": the point cloud lies outside the bounds", setting_bounds);
  r.points = cells.size() / 3;
  r.plan = plan_vdb_build(o, r.points, grid, {o.memory ? o.memory : default_host_memory(), dev.memory_budget()});
  if (on_plan) on_plan(r.plan);
  lap("read");
  const uint32_t levels = static_cast<uint32_t>(std::lround(std::log2(double(resolution))));
  double colour_seconds = 0;
  auto t = Clock::now();
  CloudVoxels voxels = voxelize_cloud(dev, cells, rgb, levels, &colour_seconds);
  cells = {};
  rgb = {};
  const double total = std::chrono::duration<double>(Clock::now() - t).count();
  r.seconds.push_back({"voxelize", total - colour_seconds});
  if (!voxels.colours.empty()) r.seconds.push_back({"colours", colour_seconds});
  r.resolution = resolution;
  r.voxels = voxels.keys.size();
  const bool symmetric = o.encoding == Encoding::ussvdag || o.encoding == Encoding::ssvdag;
  DagBuildTimes times;
  Dag dag = build_dag_for_format(dev, voxels.keys, levels, o.encoding, &times);
  voxels.keys = {};
  r.seconds.push_back({"svo", times.svo_seconds});
  r.seconds.push_back(
      {o.encoding == Encoding::svo ? "encode octree" : symmetric ? "ssvdag" : "svdag", times.reduce_seconds});
  t = Clock::now();
  MvxFile file = mvx_for_dag(dag, o.encoding, grid, bounds);
  r.seconds.push_back({"encode", std::chrono::duration<double>(Clock::now() - t).count()});
  if (attach_colours(dev, file, std::move(voxels.colours), o, r))
    r.seconds.push_back({"quantize", r.colour_quantize.seconds});
  t = Clock::now();
  const MvxColourStats colour = write_mvx(o.output, file, o.paging);
  r.seconds.push_back({"write", std::chrono::duration<double>(Clock::now() - t).count()});
  r.grid = grid;
  r.svo_nodes = file.svo_nodes;
  r.nodes_per_level = file.dag_nodes;
  r.nodes_total = nodes_total(file);
  r.bytes = file.dag.bytes();
  r.bits_per_voxel = r.voxels ? 8.0 * double(r.bytes) / double(r.voxels) : 0;
  report_colours(file, colour, r);
}

bool attach_colours(Device& dev, MvxFile& file, std::vector<uint8_t> colours, const BuildOptions& o, BuildReport& r) {
  file.colours = std::move(colours);
  if (file.colours.empty() || o.colour_bits >= 24) return false;
  r.colour_quantize = quantize_colours(dev, file.colours, o.colour_bits);
  file.colour_bits = o.colour_bits;
  return true;
}

void report_colours(const MvxFile& file, const MvxColourStats& colour, BuildReport& r) {
  if (file.colours.empty()) return;
  r.attributes = "rgb";
  r.colour_entries = file.colours.size() / 3;
  r.colour_bytes = colour.bytes;
  r.colour_format = colour.format == 1 ? "palette" : "raw";
  r.colour_palette_bytes = colour.palette_bytes;
  r.colour_palette_seconds = colour.palette_seconds;
  r.colour_bits_per_voxel = file.voxels ? 8.0 * double(r.colour_bytes) / double(file.voxels) : 0;
}

}  // namespace mv

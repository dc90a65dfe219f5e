// The main job, stage by stage: read -> voxelize -> octree -> DAG -> encode -> write.
#include <chrono>
#include <cmath>

#include "io/mesh_source.h"
#include "io/vdb_source.h"
#include "megavox/build.h"
#include "megavox/dag.h"
#include "megavox/encode.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "megavox/voxelize.h"

namespace mv {

namespace {
using Clock = std::chrono::steady_clock;
constexpr size_t kBatchTriangles = 1u << 20;
}  // namespace

uint32_t parse_resolution(const std::string& text) {
  uint64_t n = 0;
  try {
    n = parse_size(text);
  } catch (const Error&) {
    throw Error("--resolution '" + text + "' is not a number of voxels per axis (examples: 1024, 2K, 16K)");
  }
  if (n < 2 || n > (1u << 21) || (n & (n - 1)))
    throw Error("--resolution " + text + " must be a power of two from 2 to 2M voxels per axis");
  return static_cast<uint32_t>(n);
}

namespace {

struct Voxels {
  std::vector<uint64_t> keys;
  GridTransform grid;
  Bounds bounds;
};

// A mesh: bounds of the vertices the faces use (scans carry unreferenced vertices), the grid, then the
// triangles voxelized in batches on the device.
Voxels voxelize_mesh(Device& dev, const BuildOptions& o, uint32_t resolution, BuildReport& r,
                     const std::function<void(const std::string&, double)>& report) {
  Voxels v;
  std::vector<uint32_t> idx;
  {
    auto mesh = io::open_mesh(o.input);
    const auto& pos = mesh->positions();
    std::vector<bool> used(pos.size() / 3, false);
    while (mesh->next_triangles(idx, kBatchTriangles))
      for (uint32_t i : idx) used[i] = true;
    for (size_t i = 0; i < used.size(); ++i)
      if (used[i]) v.bounds.extend(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
  }
  if (v.bounds.empty()) throw Error(o.input + ": the mesh has no triangles");
  v.grid = grid_for_bounds(v.bounds, resolution);
  auto mesh = io::open_mesh(o.input);
  Voxelizer vox(dev, resolution);
  std::vector<float> tris;
  const double faces = std::max<double>(1, double(mesh->triangles_hint()));
  while (mesh->next_triangles(idx, kBatchTriangles)) {
    tris.clear();
    triangles_to_grid(v.grid, mesh->positions(), idx.data(), idx.size() / 3, tris);
    vox.add(tris);
    report("voxelize", std::min(1.0, double(vox.triangles()) / faces));
  }
  v.keys = vox.take_keys();
  r.triangles = vox.triangles();
  return v;
}

}  // namespace

BuildReport build_mvx(Device& dev, const BuildOptions& o, const Progress& progress) {
  if (o.format != "svdag" && o.format != "ussvdag" && o.format != "ssvdag")
    throw Error("--format " + o.format + ": this build writes svdag, ussvdag and ssvdag (svo is not implemented "
                "yet)");
  BuildReport r;
  r.input = o.input;
  r.output = o.output;
  r.format = o.format;
  auto report = [&](const std::string& stage, double f) {
    if (progress) progress(stage, f);
  };
  auto t = Clock::now();
  auto lap = [&](const std::string& stage) {
    auto now = Clock::now();
    r.seconds.push_back({stage, std::chrono::duration<double>(now - t).count()});
    t = now;
  };

  report("read", 0);
  Voxels voxels;
  if (io::is_vdb(o.input)) {
    io::VdbVoxels vdb = io::read_vdb(o.input, o.grid, o.resolution);
    r.vdb_grid = vdb.grid_name;
    r.vdb_class = vdb.grid_class;
    voxels = {std::move(vdb.keys), vdb.grid, vdb.bounds};
    lap("read");
  } else {
    voxels = voxelize_mesh(dev, o, o.resolution ? o.resolution : 1024, r, report);
    lap("voxelize");
  }
  const uint32_t resolution = voxels.grid.resolution;
  if (o.format == "ssvdag" && resolution < 8) throw Error("--format ssvdag needs a resolution of at least 8");
  const uint32_t levels = static_cast<uint32_t>(std::log2(double(resolution)) + 0.5);
  r.resolution = resolution;
  r.voxels = voxels.keys.size();
  const GridTransform grid = voxels.grid;
  const Bounds bounds = voxels.bounds;

  report("dag", 0);
  DagBuildTimes times;
  const bool symmetric = o.format != "svdag";
  Dag dag = symmetric ? build_ssvdag(dev, voxels.keys, levels, &times) : build_svdag(dev, voxels.keys, levels, &times);
  voxels = {};
  r.seconds.push_back({"svo", times.svo_seconds});
  r.seconds.push_back({symmetric ? "ssvdag" : "svdag", times.reduce_seconds});
  t = Clock::now();

  report("encode", 0);
  MvxFile file;
  file.grid = grid;
  file.bounds = bounds;
  file.voxels = dag.voxels;
  file.svo_nodes = dag.svo_nodes;
  file.dag_nodes.push_back(dag.voxels);
  for (uint32_t l = 1; l <= levels; ++l) file.dag_nodes.push_back(dag.nodes(l));
  file.dag = o.format == "ssvdag" ? encode_ssvdag(dag) : encode_svdag(dag);
  lap("encode");
  report("write", 0);
  write_mvx(o.output, file);
  lap("write");

  r.svo_nodes = file.svo_nodes;
  r.nodes_per_level = file.dag_nodes;
  for (uint32_t l = 2; l <= levels; ++l) r.nodes_total += file.dag_nodes[l];
  r.bytes = file.dag.bytes();
  r.bits_per_voxel = r.voxels ? 8.0 * double(r.bytes) / double(r.voxels) : 0;
  return r;
}

}  // namespace mv

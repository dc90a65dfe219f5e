// The main job, stage by stage: read -> voxelize -> octree -> DAG -> encode -> write.
#include <algorithm>
#include <chrono>
#include <functional>
#include <cmath>
#include <unistd.h>

#include "io/mesh_source.h"
#include "io/vdb_source.h"
#include "build_steps.h"
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

uint64_t default_host_memory() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) / 2 : uint64_t{4} << 30;
}

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

Voxelizer::Rule rule(const BuildOptions& o) {
  return o.voxelize == "thin" ? Voxelizer::Rule::kThin : Voxelizer::Rule::kConservative;
}

uint64_t memory_budget(const BuildOptions& o) { return o.memory ? o.memory : default_host_memory(); }

// Fails early, before the heavy work, when a mesh's host-side arrays would pass the budget.
void check_mesh_memory(const BuildOptions& o, const io::MeshSource& mesh, bool all_triangles) {
  const uint64_t vertices = mesh.positions().size() / 3, triangles = mesh.triangles_hint();
  // positions and the used-vertex flags; then either one batch of triangles or all of them in grid units
  // with their indices and the per-cube bucket entries
  uint64_t need = vertices * 13 + (all_triangles ? triangles * (12 + 36 + 4) : std::min<uint64_t>(triangles, kBatchTriangles) * 48);
  if (need > memory_budget(o))
    throw Error(o.input + ": the mesh needs about " + std::to_string((need + (1 << 20) - 1) >> 20) +
                " MiB of host memory, over --memory " + std::to_string(memory_budget(o) >> 20) + " MiB");
}

bool clips(const BuildOptions& o) { return o.placement.origin == GridPlacement::Origin::kCube; }

// The grid around a mesh's bounds; with an explicit cube the stored bounds become the part inside it.
GridTransform place_mesh_grid(const BuildOptions& o, uint32_t resolution, Bounds& bounds) {
  if (bounds.empty()) throw Error(o.input + ": the mesh has no triangles");
  GridTransform g = grid_for_bounds(bounds, resolution, o.placement);
  if (clips(o)) {
    const double side = g.voxel_size * g.resolution;
    for (int a = 0; a < 3; ++a) {
      bounds.lo[a] = std::max(bounds.lo[a], g.origin[a]);
      bounds.hi[a] = std::min(bounds.hi[a], g.origin[a] + side);
    }
    if (bounds.empty() || bounds.lo[1] > bounds.hi[1] || bounds.lo[2] > bounds.hi[2])
      throw Error(o.input + ": the mesh lies outside --bounds");
  }
  return g;
}

// A mesh: bounds of the vertices the faces use (scans carry unreferenced vertices), the grid, then the
// triangles voxelized in batches on the device.
Voxels voxelize_mesh(Device& dev, const BuildOptions& o, uint32_t resolution, BuildReport& r,
                     const std::function<void(const std::string&, double)>& report) {
  Voxels v;
  std::vector<uint32_t> idx;
  {
    auto mesh = io::open_mesh(o.input);
    check_mesh_memory(o, *mesh, false);
    const auto& pos = mesh->positions();
    std::vector<bool> used(pos.size() / 3, false);
    while (mesh->next_triangles(idx, kBatchTriangles))
      for (uint32_t i : idx) used[i] = true;
    for (size_t i = 0; i < used.size(); ++i)
      if (used[i]) v.bounds.extend(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
  }
  v.grid = place_mesh_grid(o, resolution, v.bounds);
  auto mesh = io::open_mesh(o.input);
  Voxelizer vox(dev, resolution, rule(o));
  vox.limit_host_memory(memory_budget(o));
  std::vector<float> tris;
  const double faces = std::max<double>(1, double(mesh->triangles_hint()));
  while (mesh->next_triangles(idx, kBatchTriangles)) {
    tris.clear();
    triangles_to_grid(v.grid, mesh->positions(), idx.data(), idx.size() / 3, tris, clips(o));
    vox.add(tris);
    report("voxelize", std::min(1.0, double(vox.triangles()) / faces));
  }
  v.keys = vox.take_keys();
  r.triangles = vox.triangles();
  return v;
}

// The mesh's triangles in grid units, all in memory (9 floats each), and the grid.
struct GridMesh {
  std::vector<float> tris;
  GridTransform grid;
  Bounds bounds;
};

GridMesh load_grid_mesh(const BuildOptions& o, uint32_t resolution) {
  GridMesh m;
  auto mesh = io::open_mesh(o.input);
  check_mesh_memory(o, *mesh, true);
  std::vector<uint32_t> idx, all;
  while (mesh->next_triangles(idx, kBatchTriangles)) all.insert(all.end(), idx.begin(), idx.end());
  const auto& pos = mesh->positions();
  for (uint32_t v : all) m.bounds.extend(pos[3 * size_t{v}], pos[3 * size_t{v} + 1], pos[3 * size_t{v} + 2]);
  m.grid = place_mesh_grid(o, resolution, m.bounds);
  triangles_to_grid(m.grid, pos, all.data(), all.size() / 3, m.tris, clips(o));
  return m;
}

using Lap = std::function<void(const std::string&)>;
using Report = std::function<void(const std::string&, double)>;

void encode_and_write(const Dag& dag, const BuildOptions& o, const GridTransform& grid, const Bounds& bounds,
                      BuildReport& r, const Lap& lap) {
  MvxFile file = mvx_for_dag(dag, o.format, grid, bounds);
  lap("encode");
  write_mvx(o.output, file);
  lap("write");
  r.grid = grid;
  r.voxels = dag.voxels;
  r.svo_nodes = file.svo_nodes;
  r.nodes_per_level = file.dag_nodes;
  r.nodes_total = nodes_total(file);
  r.bytes = file.dag.bytes();
  r.bits_per_voxel = r.voxels ? 8.0 * double(r.bytes) / double(r.voxels) : 0;
}

// A mesh at a resolution above the cube size: triangles are bucketed by the cubes their bounding boxes
// meet, then each non-empty cube is voxelized and reduced alone and the partial DAGs merged
// (build_dag_by_cubes): device memory holds one cube's voxels at a time. The triangles stay in host memory.
BuildReport build_out_of_core(Device& dev, const BuildOptions& o, uint32_t resolution, BuildReport& r,
                              const Report& report, const Lap& lap) {
  if (o.cube < 8 || (o.cube & (o.cube - 1))) throw Error("--cube " + std::to_string(o.cube) + " must be a power of two >= 8");
  GridMesh m = load_grid_mesh(o, resolution);
  lap("read");
  r.resolution = resolution;
  r.cube = o.cube;
  r.triangles = m.tris.size() / 9;
  const uint32_t per_axis = resolution / o.cube;
  std::vector<std::vector<uint32_t>> bucket(size_t{per_axis} * per_axis * per_axis);
  for (uint32_t t = 0; t < r.triangles; ++t) {
    uint32_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const float* v = &m.tris[9 * size_t{t}];
      double mn = std::min({double(v[a]), double(v[3 + a]), double(v[6 + a])});
      double mx = std::max({double(v[a]), double(v[3 + a]), double(v[6 + a])});
      lo[a] = std::min<uint32_t>(per_axis - 1, static_cast<uint32_t>(std::max(0.0, std::floor(mn)) / o.cube));
      hi[a] = std::min<uint32_t>(per_axis - 1, static_cast<uint32_t>(std::max(0.0, std::floor(mx)) / o.cube));
    }
    for (uint32_t x = lo[0]; x <= hi[0]; ++x)
      for (uint32_t y = lo[1]; y <= hi[1]; ++y)
        for (uint32_t z = lo[2]; z <= hi[2]; ++z) bucket[(size_t{z} * per_axis + y) * per_axis + x].push_back(t);
  }
  const uint32_t levels = static_cast<uint32_t>(std::lround(std::log2(double(resolution))));
  const uint32_t cube_levels = static_cast<uint32_t>(std::lround(std::log2(double(o.cube))));
  uint64_t done = 0;
  const double cubes = double(per_axis) * per_axis * per_axis;
  std::vector<float> tris;
  CubeVoxels voxels_of = [&](uint32_t x, uint32_t y, uint32_t z, uint32_t size) {
    report("cubes", double(++done) / cubes);
    const auto& ts = bucket[(size_t{z / size} * per_axis + y / size) * per_axis + x / size];
    if (ts.empty()) return std::vector<uint64_t>();
    tris.clear();
    for (uint32_t t : ts) tris.insert(tris.end(), m.tris.begin() + 9 * size_t{t}, m.tris.begin() + 9 * size_t{t} + 9);
    Voxelizer v(dev, resolution, rule(o));
    v.limit_host_memory(memory_budget(o));
    v.restrict_to(x, y, z, size);
    v.add(tris);
    return v.take_keys();
  };
  const bool symmetric = o.format == "ussvdag" || o.format == "ssvdag";
  DagBuildTimes times;
  Dag dag = build_dag_by_cubes(dev, levels, cube_levels, symmetric, voxels_of, &times);
  r.seconds.push_back({"voxelize+cubes", times.svo_seconds});
  r.seconds.push_back({symmetric ? "merge ssvdag" : "merge svdag", times.reduce_seconds});
  lap("total dag");
  r.seconds.pop_back();
  encode_and_write(dag, o, m.grid, m.bounds, r, lap);
  return r;
}

}  // namespace

Dag build_dag_for_format(Device& dev, const std::vector<uint64_t>& keys, uint32_t levels, const std::string& format,
                         DagBuildTimes* times) {
  if (format == "ssvdag" && levels < 3) throw Error("--format ssvdag needs a resolution of at least 8");
  if (format == "svo") return build_svo(dev, keys, levels, times);
  if (format == "ussvdag" || format == "ssvdag") return build_ssvdag(dev, keys, levels, times);
  if (format == "svdag") return build_svdag(dev, keys, levels, times);
  throw Error("--format " + format + ": choose svo, svdag, ussvdag or ssvdag");
}

MvxFile mvx_for_dag(const Dag& dag, const std::string& format, const GridTransform& grid, const Bounds& bounds) {
  MvxFile file;
  file.grid = grid;
  file.bounds = bounds;
  file.voxels = dag.voxels;
  file.svo_nodes = dag.svo_nodes;
  file.dag_nodes.push_back(dag.voxels);
  for (uint32_t l = 1; l <= dag.levels; ++l) file.dag_nodes.push_back(dag.nodes(l));
  file.dag = format == "ssvdag" ? encode_ssvdag(dag) : encode_svdag(dag);
  return file;
}

uint64_t nodes_total(const MvxFile& file) {
  uint64_t total = 0;
  for (size_t l = 2; l < file.dag_nodes.size(); ++l) total += file.dag_nodes[l];
  return total;
}

BuildReport build_mvx(Device& dev, const BuildOptions& o, const Progress& progress) {
  if (o.format != "svo" && o.format != "svdag" && o.format != "ussvdag" && o.format != "ssvdag")
    throw Error("--format " + o.format + ": choose svo, svdag, ussvdag or ssvdag");
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
  const uint32_t mesh_resolution = o.resolution ? o.resolution : 1024;
  const bool vdb = io::is_vdb(o.input);
  if (o.voxelize != "conservative" && o.voxelize != "thin")
    throw Error("--voxelize " + o.voxelize + ": choose conservative or thin");
  if (vdb && (o.placement.origin != GridPlacement::Origin::kCenter || o.voxelize != "conservative"))
    throw Error(o.input + ": --grid-origin, --bounds and --voxelize apply to meshes; a .vdb keeps its own voxels");
  if (!vdb) {
    r.grid_origin = to_string(o.placement.origin);
    r.voxelize = o.voxelize;
  }
  if (!vdb && o.cube && mesh_resolution > o.cube) {
    if (o.format == "svo")
      throw Error("--format svo builds in core (the plain octree of the whole grid in device memory): add --cube 0");
    return build_out_of_core(dev, o, mesh_resolution, r, report, lap);
  }
  if (o.format == "ssvdag" && o.resolution && o.resolution < 8) throw Error("--format ssvdag needs a resolution of at least 8");
  Voxels voxels;
  if (vdb) {
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

  const bool symmetric = o.format == "ussvdag" || o.format == "ssvdag";
  DagBuildTimes times;
  Dag dag = build_dag_for_format(dev, voxels.keys, levels, o.format, &times);
  voxels = {};
  r.seconds.push_back({"svo", times.svo_seconds});
  r.seconds.push_back({o.format == "svo" ? "encode octree" : symmetric ? "ssvdag" : "svdag", times.reduce_seconds});
  t = Clock::now();
  encode_and_write(dag, o, grid, bounds, r, lap);
  return r;
}

}  // namespace mv

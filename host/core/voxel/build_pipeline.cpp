// The main job, stage by stage: read -> voxelize -> octree -> DAG -> encode -> write.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <optional>
#include <filesystem>
#include <functional>
#include <cmath>
#include <memory>
#include <unistd.h>

#include "io/cloud_input.h"
#include "voxel/cube_hooks.h"
#include "voxel/mesh_shares.h"
#include "voxel/mesh_walk.h"
#include "io/mesh_source.h"
#include "io/output_path.h"
#include "io/vdb_source.h"
#include "voxel/build_plan.h"
#include "voxel/build_steps.h"
#include "voxel/mesh_colours.h"
#include "megavox/build.h"
#include "voxel/triangle_buckets.h"
#include "megavox/dag.h"
#include "megavox/encode.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "megavox/voxelize.h"
#include "option_words.h"

namespace mv {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

namespace {
std::atomic<uint32_t> g_host_memory_share{1};
}  // namespace

void set_host_memory_share(uint32_t processes) { g_host_memory_share = std::max(1u, processes); }

uint64_t default_host_memory() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  const uint64_t half = pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) / 2 : uint64_t{4} << 30;
  return half / g_host_memory_share;
}

uint32_t parse_resolution(const std::string& text) {
  uint64_t n = 0;
  try {
    n = parse_size(text);
  } catch (const Error&) {
    throw CodedError(ErrorCode::invalid_argument,
                     "resolution '" + text + "' is not a number of voxels per axis (examples: 1024, 2K, 16K)",
                     setting_resolution);
  }
  if (n < 2 || n > (1u << 21) || (n & (n - 1)))
    throw CodedError(ErrorCode::invalid_argument,
                     "resolution " + text + " must be a power of two from 2 to 2M voxels per axis", setting_resolution);
  return static_cast<uint32_t>(n);
}

namespace {

struct Voxels {
  Bricks bricks;
  GridTransform grid;
  Bounds bounds;
};

Voxelizer::Rule rule(const BuildOptions& o) { return o.voxelize; }

// Fails before anything is read when the cubes alone would pass the buckets' share of the budget: a resolution
// far above --cube makes (resolution / cube)^3 cubes (1M in 1024^3 cubes: 2^30 of them, 48 GiB of table).
void check_cube_table(const BuildOptions& o, uint32_t resolution) {
  const uint64_t need = TriangleBuckets::table_bytes(resolution / o.cube);
  if (need <= bucket_share(o)) return;
  uint32_t cube = o.cube;  // the smallest cube size whose table fits, if any does
  while (cube < resolution && TriangleBuckets::table_bytes(resolution / cube) > bucket_share(o)) cube *= 2;
  const uint64_t per_axis = resolution / o.cube;
  throw CodedError(ErrorCode::out_of_memory,
                   "resolution " + std::to_string(resolution) + " in cubes of " + std::to_string(o.cube) + "^3 makes " +
                       std::to_string(per_axis * per_axis * per_axis) + " cubes, whose table alone needs " +
                       format_bytes(need) + " of host memory, over the quarter of the host memory budget " +
                       format_bytes(memory_budget(o)) + " it may use; raise the cube size to " + std::to_string(cube) +
                       " or more, or lower the resolution",
                   setting_cube | setting_resolution | setting_host_memory);
}

// A mesh: its bounds, the grid, then the triangles voxelized in batches on the device; `read_seconds`: the time
// spent reading the file (its survey, and opening it again where its source cannot walk its faces again).
Voxels voxelize_mesh(Device& dev, const BuildOptions& o, uint32_t resolution, BuildReport& r,
                     const std::function<void(const std::string&, double)>& report, const PlanListener& on_plan,
                     MeshColourInput* colours, double& read_seconds) {
  Voxels v;
  const auto start = std::chrono::steady_clock::now();
  MeshSurvey survey = survey_mesh(o, &r);
  read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  v.grid = plan_mesh(o, resolution, survey, dev, r, on_plan);
  v.bounds = survey.bounds;
  Voxelizer vox(dev, resolution, rule(o));
  vox.limit_host_memory(memory_budget(o) - vertex_share(o));
  uint64_t triangles = 0;
  double reopen_seconds = 0;
  for_each_grid_batch(
      o, v.grid, triangles,
      [&](const std::vector<float>& tris, double done) {
        if (colours && colours->wanted) vox.record_fragments();
        vox.add(tris);
        report("voxelize", done);
      },
      colours, false, nullptr, &reopen_seconds, std::move(survey.source));
  read_seconds += reopen_seconds;
  v.bricks = vox.take_bricks();
  if (colours) colours->fragments = vox.take_fragments();
  r.triangles = vox.triangles();
  return v;
}

using Lap = std::function<void(const std::string&)>;
using Report = std::function<void(const std::string&, double)>;

void encode_and_write(Device& dev, const Dag& dag, const BuildOptions& o, const GridTransform& grid,
                      const Bounds& bounds, BuildReport& r, const Lap& lap, const Report& report,
                      std::vector<uint8_t> colours = {}) {
  MvxFile file = mvx_for_dag(dag, o.encoding, grid, bounds);
  lap("encode");
  if (attach_colours(dev, file, std::move(colours), o, r)) lap("quantize");
  report("write", 0);
  const MvxColourStats stats = write_mvx(o.output, file, o.paging);
  lap("write");  // no report after the write: a cancel there would come too late
  report_colours(file, stats, r);
  r.grid = grid;
  r.voxels = dag.voxels;
  r.svo_nodes = file.svo_nodes;
  r.nodes_per_level = file.dag_nodes;
  r.nodes_total = nodes_total(file);
  r.bytes = file.dag.bytes();
  r.bits_per_voxel = r.voxels ? 8.0 * double(r.bytes) / double(r.voxels) : 0;
}

// A mesh at a resolution above the cube size: triangles are bucketed by the cubes their bounding boxes
// meet (spilling to a temporary file past a quarter of --memory), then each non-empty cube is voxelized and
// reduced alone and the partial DAGs merged (build_dag_by_cubes): device memory holds one cube's voxels at a
// time, host memory the vertex positions, a batch of triangles, a share of the buckets and one cube's keys.
BuildReport build_out_of_core(Device& dev, const BuildOptions& o, uint32_t resolution, BuildReport& r,
                              const Report& report, const Lap& lap, const PlanListener& on_plan) {
  if (o.cube < 8 || (o.cube & (o.cube - 1)))
    throw CodedError(ErrorCode::invalid_argument,
                     "cube size " + std::to_string(o.cube) + " must be a power of two >= 8", setting_cube);
  check_cube_table(o, resolution);
  MeshSurvey survey = survey_mesh(o, &r, true);
  const GridTransform grid = plan_mesh(o, resolution, survey, dev, r, on_plan);
  const Bounds bounds = survey.bounds;
  r.resolution = resolution;
  r.cube = o.cube;
  const uint32_t per_axis = resolution / o.cube;
  // With colours a bucket holds records: the triangle, then its colours and its index in the mesh (kColourRecord).
  MeshColourInput colours;
  colours.keep_tris = false;
  std::unique_ptr<TriangleBuckets> buckets;
  std::vector<float> records;
  for_each_grid_batch(
      o, grid, r.triangles,
      [&](const std::vector<float>& tris, double done) {
        if (!buckets)
          buckets = std::make_unique<TriangleBuckets>(per_axis, o.cube, bucket_share(o), colours.wanted ? kColourRecord : 9);
        if (!colours.wanted) {
          buckets->add(tris);
        } else {
          coloured_records(tris, colours.colours, records);
          buckets->add(records);
        }
        report("read", done);
      },
      &colours, survey.face_shares, survey.share.get(), nullptr, std::move(survey.source));
  if (!buckets) buckets = std::make_unique<TriangleBuckets>(per_axis, o.cube, bucket_share(o), colours.wanted ? kColourRecord : 9);
  std::vector<uint64_t> dealt;  // over ranks reading shares of the faces: the estimates the cubes are dealt by
  if (survey.face_shares) {
    dealt = send_triangles_to_cube_owners(*o.ranks->collectives, *buckets, per_axis, r.triangles, r.bytes_exchanged);
    r.bytes_read = survey.bytes_read;
    r.bytes_exchanged += survey.bytes_exchanged;
  }
  r.spilled_bytes = buckets->spilled_bytes();
  lap("read");
  CubeColours gathered;  // every cube's voxels and their colours, for the depth-first array
  const std::optional<CubeExchange> exchange = cube_hooks(o, *buckets, per_axis, colours.wanted ? &gathered : nullptr,
                                                          r.cubes_resumed, survey.face_shares ? &dealt : nullptr);
  std::vector<uint64_t>& colour_keys = gathered.keys;
  std::vector<uint32_t>& colour_rgb = gathered.rgb;
  const CubeExchange* ex = exchange ? &*exchange : nullptr;
  const uint32_t levels = static_cast<uint32_t>(std::lround(std::log2(double(resolution))));
  const uint32_t cube_levels = static_cast<uint32_t>(std::lround(std::log2(double(o.cube))));
  uint64_t done = 0;
  const double cubes = double(per_axis) * per_axis * per_axis;
  CubeVoxels voxels_of = [&](uint32_t x, uint32_t y, uint32_t z, uint32_t size) {
    report("cubes", double(++done) / cubes);
    gathered.cube_at = colour_keys.size();
    std::vector<float> tris = buckets->take(x / size, y / size, z / size);
    MeshTriangleColours cube_colours;
    if (colours.wanted) split_records(tris, cube_colours);
    if (tris.empty()) return Bricks();
    Voxelizer v(dev, resolution, rule(o));
    v.limit_host_memory(memory_budget(o) - vertex_share(o) - bucket_share(o));
    v.restrict_to(x, y, z, size);
    if (colours.wanted) v.record_fragments();
    v.add(tris);
    Bricks bricks = v.take_bricks();
    if (colours.wanted && !bricks.empty()) {
      MeshVoxelValues values =
          mesh_voxel_values(dev, bricks, v.take_fragments(), tris, cube_colours, colours.colours.textures);
      const size_t at = colour_keys.size();
      colour_keys.resize(at + values.voxels);
      colour_rgb.resize(at + values.voxels);
      dev.download(values.keys, colour_keys.data() + at, values.voxels * 8);
      dev.download(values.rgb, colour_rgb.data() + at, values.voxels * 4);
    }
    return bricks;
  };
  const bool symmetric = o.encoding == Encoding::ussvdag || o.encoding == Encoding::ssvdag;
  DagBuildTimes times;
  Dag dag = o.encoding == Encoding::svo ? build_svo_by_cubes(dev, levels, cube_levels, voxels_of, &times, ex)
                               : build_dag_by_cubes(dev, levels, cube_levels, symmetric, voxels_of, &times, ex);
  r.seconds.push_back({"voxelize+cubes", times.svo_seconds});
  r.seconds.push_back({o.encoding == Encoding::svo ? "merge octree" : symmetric ? "merge ssvdag" : "merge svdag",
                       times.reduce_seconds});
  lap("total dag");
  r.seconds.pop_back();
  if (o.ranks && !o.ranks->writes) {  // this process's cubes are with the merging one
    r.grid = grid;
    r.voxels = dag.voxels;
    return r;
  }
  std::vector<uint8_t> depth_first;
  if (colours.wanted) {
    depth_first = cube_colours_depth_first(dev, o.input, colour_keys, colour_rgb, levels);
    lap("colours");
  }
  encode_and_write(dev, dag, o, grid, bounds, r, lap, report, std::move(depth_first));
  if (!o.resume_dir.empty()) std::filesystem::remove_all(o.resume_dir);  // the output holds every cube now
  return r;
}

}  // namespace

namespace {
// The ssvdag's compact encoding keeps level-2 bricks below at least one inner level.
void check_ssvdag_resolution(Encoding encoding, uint32_t resolution) {
  if (encoding == Encoding::ssvdag && resolution < 8)
    throw CodedError(ErrorCode::invalid_argument, "the ssvdag encoding needs a resolution of at least 8",
                     setting_encoding | setting_resolution);
}

template <class Voxels>
Dag dag_for_format(Device& dev, const Voxels& voxels, uint32_t levels, Encoding encoding, DagBuildTimes* times) {
  check_ssvdag_resolution(encoding, levels < 31 ? 1u << levels : UINT32_MAX);
  switch (encoding) {
    case Encoding::svo: return build_svo(dev, voxels, levels, times);
    case Encoding::ussvdag:
    case Encoding::ssvdag: return build_ssvdag(dev, voxels, levels, times);
    case Encoding::svdag: return build_svdag(dev, voxels, levels, times);
  }
  throw CodedError(ErrorCode::invalid_argument, "encoding " + std::to_string(static_cast<uint32_t>(encoding)) +
                                                    " is none of svo, svdag, ussvdag or ssvdag",
                   setting_encoding);
}
}  // namespace

Dag build_dag_for_format(Device& dev, const Bricks& bricks, uint32_t levels, Encoding format,
                         DagBuildTimes* times) {
  return dag_for_format(dev, bricks, levels, format, times);
}

Dag build_dag_for_format(Device& dev, const std::vector<uint64_t>& keys, uint32_t levels, Encoding format,
                         DagBuildTimes* times) {
  return dag_for_format(dev, keys, levels, format, times);
}

MvxFile mvx_for_dag(const Dag& dag, Encoding format, const GridTransform& grid, const Bounds& bounds) {
  MvxFile file;
  file.grid = grid;
  file.bounds = bounds;
  file.voxels = dag.voxels;
  file.svo_nodes = dag.svo_nodes;
  file.dag_nodes.push_back(dag.voxels);
  for (uint32_t l = 1; l <= dag.levels; ++l) file.dag_nodes.push_back(dag.nodes(l));
  file.dag = format == Encoding::ssvdag ? encode_ssvdag(dag) : encode_svdag(dag);
  return file;
}

uint64_t nodes_total(const MvxFile& file) {
  uint64_t total = 0;
  for (size_t l = 2; l < file.dag_nodes.size(); ++l) total += file.dag_nodes[l];
  return total;
}

namespace {

BuildReport build_once(Device& dev, const BuildOptions& o, const Progress& progress, const PlanListener& on_plan) {
  BuildReport r;
  r.input = o.input;
  r.output = o.output;
  r.format = encoding_name(o.encoding);
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
  const bool vdb = !o.mesh && io::is_vdb(o.input);
  if (vdb && (o.placement.origin != GridPlacement::Origin::kCenter || o.voxelize != Voxelizer::Rule::kConservative))
    throw CodedError(ErrorCode::invalid_argument,
                     o.input + ": the grid origin, the bounds and the voxelization rule apply to meshes; a .vdb keeps "
                               "its own voxels",
                     setting_grid_origin | setting_bounds | setting_voxelize);
  if (!vdb) {
    r.grid_origin = to_string(o.placement.origin);
    r.voxelize = voxelize_rule_name(o.voxelize);
  }
  const bool cloud = !vdb && !o.mesh && io::is_point_cloud(o.input);
  const bool by_cubes = !vdb && !cloud && o.cube && mesh_resolution > o.cube;
  if (!o.resume_dir.empty() && !by_cubes)
    throw CodedError(ErrorCode::invalid_argument,
                     "--resume keeps the cubes of a build in cubes (a mesh at a resolution above --cube); this build "
                     "is in one piece",
                     setting_cube);
  // Spread over processes, only a mesh built in cubes is shared out; anything else the writing one builds alone.
  if (o.ranks && !o.ranks->writes && !by_cubes) return r;
  if (cloud) {
    if (o.resolution) check_ssvdag_resolution(o.encoding, o.resolution);
    r.grid_origin = to_string(o.placement.origin);
    r.voxelize = "points";
    build_cloud(dev, o, r, lap, on_plan);
    return r;
  }
  if (!vdb && o.cube && mesh_resolution > o.cube) {
    return build_out_of_core(dev, o, mesh_resolution, r, report, lap, on_plan);
  }
  if (o.resolution) check_ssvdag_resolution(o.encoding, o.resolution);
  Voxels voxels;
  MeshColourInput mesh_colours;
  if (vdb) {
    io::VdbVoxels vdb = io::read_vdb(o.input, o.grid, o.resolution);
    r.vdb_grid = vdb.grid_name;
    r.vdb_class = vdb.grid_class;
    r.plan = plan_vdb_build(o, vdb.keys.size(), vdb.grid, plan_budgets(o, &dev));
    if (on_plan) on_plan(r.plan);
    voxels = {bricks_from_keys(vdb.keys), vdb.grid, vdb.bounds};
    vdb.keys = {};
    lap("read");
  } else {
    double read_seconds = 0;
    voxels = voxelize_mesh(dev, o, o.resolution ? o.resolution : 1024, r, report, on_plan, &mesh_colours,
                           read_seconds);
    lap("voxelize");
    // The file's reading is the read stage, as for the other inputs; a streamed PLY's faces stay in the walk.
    r.seconds.back().seconds = std::max(0.0, r.seconds.back().seconds - read_seconds);
    r.seconds.insert(r.seconds.end() - 1, {"read", read_seconds});
  }
  const uint32_t resolution = voxels.grid.resolution;
  check_ssvdag_resolution(o.encoding, resolution);
  const uint32_t levels = static_cast<uint32_t>(std::log2(double(resolution)) + 0.5);
  r.resolution = resolution;
  r.voxels = voxels.bricks.voxels();
  const GridTransform grid = voxels.grid;
  const Bounds bounds = voxels.bounds;

  std::vector<uint8_t> colours;
  if (mesh_colours.wanted) {
    try {
      colours = mesh_voxel_colours(dev, voxels.bricks, mesh_colours.fragments, mesh_colours.tris, mesh_colours.colours,
                                   levels);
    } catch (const DeviceMemoryError& e) {  // not retried in cubes: those do not carry colours
      throw CodedError(ErrorCode::out_of_memory,
                       o.input + ": the voxel colours of " + std::to_string(voxels.bricks.voxels()) +
                           " voxels do not fit device memory (" + e.what() +
                           "): raise --device-memory, lower the resolution, or build without colours (--attributes none)",
                       setting_device_memory | setting_none);
    }
    mesh_colours = {};
    lap("colours");
  }
  const bool symmetric = o.encoding == Encoding::ussvdag || o.encoding == Encoding::ssvdag;
  DagBuildTimes times;
  Dag dag = build_dag_for_format(dev, voxels.bricks, levels, o.encoding, &times);
  voxels = {};
  r.seconds.push_back({"svo", times.svo_seconds});
  r.seconds.push_back(
      {o.encoding == Encoding::svo ? "encode octree" : symmetric ? "ssvdag" : "svdag", times.reduce_seconds});
  t = Clock::now();
  encode_and_write(dev, dag, o, grid, bounds, r, lap, report, std::move(colours));
  return r;
}

constexpr uint32_t kSmallestCube = 64;

}  // namespace

std::string check_output(const BuildOptions& o) {
  return io::resolve_output({o.output, io::OutputKind::kFile, "mvx", {o.mesh ? std::string() : o.input}, 0, o.no_clobber});
}

// A mesh whose cube (or whole grid, in core) runs out of device memory builds again in cubes half the size,
// down to 64^3 (the file is the same whatever the cube size); `--cube 0` (always in core), .vdb inputs and
// a merge that does not fit keep the error.
BuildReport build_mvx(Device& dev, const BuildOptions& o, const Progress& progress, const PlanListener& on_plan) {
  BuildOptions attempt = o;
  if (!o.output.empty()) attempt.output = check_output(o);
  const uint32_t resolution = o.resolution ? o.resolution : 1024;
  bool planned = false;  // the plan is announced once, not again for each retry in smaller cubes
  const PlanListener announce = [&](const BuildPlan& plan) {
    if (on_plan && !planned) on_plan(plan);
    planned = true;
  };
  for (uint32_t retries = 0;; ++retries) {
    try {
      BuildReport r = build_once(dev, attempt, progress, announce);
      r.cube_retries = retries;
      return r;
    } catch (const DeviceMemoryError& e) {
      // only a cube (or the whole grid built in core) that did not fit: the merge would not get smaller
      const bool in_core = !(attempt.cube && resolution > attempt.cube);
      const bool cube_failed = in_core || dynamic_cast<const CubeMemoryError*>(&e) != nullptr;
      const uint32_t cube = in_core ? resolution : attempt.cube;
      const bool voxels_read = !o.mesh && (io::is_vdb(o.input) || io::is_point_cloud(o.input));
      // spread over processes, the cubes are dealt once: a smaller cube is the user's to ask for
      if (!cube_failed || o.cube == 0 || cube / 2 < kSmallestCube || voxels_read || o.ranks) throw;
      attempt.cube = cube / 2;
      if (progress) progress("cubes of " + std::to_string(attempt.cube) + "^3 (device memory)", 0);
    }
  }
}

BuildPlan plan_build(const BuildOptions& o) {
  const uint32_t resolution = o.resolution ? o.resolution : 1024;
  if (!o.mesh && io::is_vdb(o.input)) {
    io::VdbVoxels vdb = io::read_vdb(o.input, o.grid, o.resolution);
    return plan_vdb_build(o, vdb.keys.size(), vdb.grid, plan_budgets(o, nullptr));
  }
  if (!o.mesh && io::is_point_cloud(o.input)) {  // the points bound the voxels
    const io::CloudPoints cloud = io::read_cloud(o.input, false);
    const GridTransform grid = grid_for_bounds(cloud.bounds, resolution, o.placement);
    return plan_vdb_build(o, cloud.xyz.size() / 3, grid, plan_budgets(o, nullptr));
  }
  MeshSurvey survey = survey_mesh(o, nullptr);
  const GridTransform grid = place_mesh_grid(o, resolution, survey.bounds);
  return plan_mesh_build(o, survey, grid, plan_budgets(o, nullptr));
}

}  // namespace mv

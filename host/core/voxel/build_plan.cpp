// Estimates of a build's size and memory from the mesh's surface (see build_plan.h). The constants were fitted
// to builds of the meshes in shared/data (bunny, igea, spot, fandisk, lionstatue; 256^3 to 4096^3). Checked
// against the counts: the voxels within 1% on every one of them and on armadillo; the output 0.8x to 1.7x the
// file's DAG (a flat model's DAG shares far more: a tetrahedron's is 7x smaller at 64^3, 2700x at 4096^3); the
// memory, against peak resident memory on PoCL less its 127 MB at rest, 0.15x to 0.9x: an order of magnitude.
#include "voxel/build_plan.h"

#include <algorithm>
#include <cmath>

namespace mv {

namespace {

// Voxels per 4^3 brick the surface meets (measured: 16.0 conservative, 10.4 to 10.9 thin).
double voxels_per_brick(Voxelizer::Rule rule) { return rule == Voxelizer::Rule::kThin ? 10.5 : 16; }

// Encoded bits per brick. The octree's (svo) stays near 340; a DAG shares more of its nodes the more bricks it
// has: an svdag's fell from 168 bits at 14K bricks to 49 at 3.6M, about as bricks^-0.22; an ssvdag is about
// 0.3 of that.
double bits_per_brick(Encoding encoding, double bricks) {
  if (encoding == Encoding::svo) return 340;
  const double dag = 168 * std::pow(std::max(bricks, 14000.0) / 14000, -0.22);
  return encoding == Encoding::ssvdag ? 0.3 * dag : dag;
}

// Memory per brick (peak resident memory over bricks, PoCL, where device memory is host memory: about 75 bytes
// in core, 67 out of core): device-side the keys and masks, their sorted copies and the sort's scratch; host-side
// the collected bricks in core, the partial DAGs kept for the merge out of core.
constexpr double kDeviceBytesPerBrick = 48;
constexpr double kHostBytesPerBrick = 32;
constexpr double kHostBytesPerBrickOutOfCore = 60;
// Past these, a build is slow enough to say so before it starts.
constexpr uint64_t kLargeOutputBytes = uint64_t{4} << 30;
constexpr uint64_t kManyCubes = 100000;
constexpr uint64_t kManyVoxels = uint64_t{1} << 30;
constexpr uint32_t kCommonResolution = 4096;  // what the time warning compares to: a build of seconds

std::string bytes_text(double bytes) { return format_bytes(static_cast<uint64_t>(bytes)); }

void check_budgets(BuildPlan& p, const PlanBudgets& budgets, bool retries_in_cubes) {
  if (budgets.host && p.host_bytes > budgets.host)
    p.warnings.push_back("estimated host memory " + bytes_text(p.host_bytes) + " is over the host memory budget " +
                         bytes_text(budgets.host) + ": the build may stop with an error, or spill to scratch files");
  if (budgets.device && p.device_bytes > budgets.device)
    p.warnings.push_back("estimated device memory " + bytes_text(p.device_bytes) + " is over the device budget " +
                         bytes_text(budgets.device) + (retries_in_cubes ? ": the cubes will be halved until one fits"
                                                                   : ": the build may fail"));
  if (p.output_bytes > kLargeOutputBytes)
    p.warnings.push_back("estimated output " + bytes_text(p.output_bytes) + " (" + std::to_string(p.voxels) +
                         " voxels): a build of hours, not minutes; a lower resolution shrinks it 4x per halving");
  if (p.voxels > kManyVoxels && p.resolution > kCommonResolution) {
    // A surface's voxels grow as the resolution squared; so, about, do the build's time and size.
    const std::string times = std::to_string(uint64_t{p.resolution / kCommonResolution} * (p.resolution / kCommonResolution));
    p.warnings.push_back("estimated " + std::to_string(p.voxels) + " voxels, " + times + "x what resolution " +
                         std::to_string(kCommonResolution) + " gives this mesh: expect about " + times +
                         "x its build time");
  }
  if (p.cubes_with_surface > kManyCubes)
    p.warnings.push_back("about " + std::to_string(p.cubes_with_surface) + " cubes of " + std::to_string(p.cube) +
                         "^3 to build one at a time; a larger cube size makes fewer");
}

BuildPlan grid_plan(const GridTransform& grid) {
  BuildPlan p;
  p.resolution = grid.resolution;
  p.voxel_size = grid.voxel_size;
  std::copy(grid.origin, grid.origin + 3, p.origin);
  return p;
}

}  // namespace

void MeshSurvey::add_triangle(const float* a, const float* b, const float* c) {
  const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
  const double v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
  // Half the cross product's components are the triangle's shadows on the three axis planes.
  const double n[3] = {std::abs(u[1] * v[2] - u[2] * v[1]) / 2, std::abs(u[2] * v[0] - u[0] * v[2]) / 2,
                       std::abs(u[0] * v[1] - u[1] * v[0]) / 2};
  area += std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  shadow_area += n[0] + n[1] + n[2];
  dominant_area += std::max({n[0], n[1], n[2]});
  ++triangles;
}

void survey_faces(io::MeshSource& mesh, size_t batch, MeshSurvey& s, std::vector<bool>& used) {
  const auto& pos = mesh.positions();
  used.assign(pos.size() / 3, false);
  std::vector<uint32_t> idx;
  while (mesh.next_triangles(idx, batch))
    for (size_t t = 0; t + 2 < idx.size(); t += 3) {
      used[idx[t]] = used[idx[t + 1]] = used[idx[t + 2]] = true;
      s.add_triangle(&pos[3 * size_t{idx[t]}], &pos[3 * size_t{idx[t + 1]}], &pos[3 * size_t{idx[t + 2]}]);
    }
}

void survey_used_vertices(std::span<const float> pos, const std::vector<bool>& used, MeshSurvey& s) {
  for (size_t i = 0; i < used.size(); ++i)
    if (used[i]) {
      s.bounds.extend(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
      ++s.vertices;
    }
}

BuildPlan plan_mesh_build(const BuildOptions& o, const MeshSurvey& s, const GridTransform& grid,
                          const PlanBudgets& budgets) {
  BuildPlan p = grid_plan(grid);
  p.triangles = s.triangles;
  p.surface_area = s.area;
  const double face = grid.voxel_size * grid.voxel_size;
  const double voxels = (o.voxelize == Voxelizer::Rule::kThin ? s.dominant_area : s.shadow_area) / face;
  const double bricks = voxels / voxels_per_brick(o.voxelize);
  p.voxels = static_cast<uint64_t>(voxels);
  p.output_bytes = static_cast<uint64_t>(bricks * bits_per_brick(o.encoding, bricks) / 8);
  const double positions = double(s.vertices) * 12;
  p.out_of_core = o.cube && grid.resolution > o.cube;
  if (p.out_of_core) {
    p.cube = o.cube;
    const uint64_t per_axis = grid.resolution / o.cube;
    p.cubes = per_axis * per_axis * per_axis;
    // A cube meets about the surface's shadow in cube faces, plus one for the cubes it only grazes.
    const double cube_face = face * o.cube * o.cube;
    p.cubes_with_surface =
        std::clamp<uint64_t>(static_cast<uint64_t>(s.shadow_area / cube_face) + 1, 1, p.cubes);
    // Device memory holds one cube's bricks at a time; the host the bucketed triangles (36 bytes each).
    p.device_bytes = static_cast<uint64_t>(bricks / double(p.cubes_with_surface) * kDeviceBytesPerBrick);
    p.host_bytes = static_cast<uint64_t>(positions + double(s.triangles) * 36 + bricks * kHostBytesPerBrickOutOfCore);
  } else {
    // Device memory also holds a batch of triangles and their work items (44 bytes each).
    p.device_bytes = static_cast<uint64_t>(bricks * kDeviceBytesPerBrick + double(s.triangles) * 44);
    p.host_bytes = static_cast<uint64_t>(positions + bricks * kHostBytesPerBrick);
  }
  check_budgets(p, budgets, o.cube != 0);
  return p;
}

BuildPlan plan_vdb_build(const BuildOptions& o, uint64_t voxels, const GridTransform& grid, const PlanBudgets& budgets) {
  BuildPlan p = grid_plan(grid);
  p.voxels = voxels;
  const double bricks = double(voxels) / voxels_per_brick(o.voxelize);
  p.output_bytes = static_cast<uint64_t>(bricks * bits_per_brick(o.encoding, bricks) / 8);
  p.device_bytes = static_cast<uint64_t>(bricks * kDeviceBytesPerBrick);
  p.host_bytes = static_cast<uint64_t>(double(voxels) * 8 + bricks * kHostBytesPerBrick);  // the keys read
  check_budgets(p, budgets, false);
  return p;
}

}  // namespace mv

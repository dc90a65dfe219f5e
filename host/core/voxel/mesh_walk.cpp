// Reading a mesh for a build: budgets, the survey and the walk (voxel/mesh_walk.h).
#include "voxel/mesh_walk.h"

#include <algorithm>
#include <chrono>
#include <string>

#include "io/memory_mesh.h"
#include "megavox/error.h"
#include "voxel/mesh_shares.h"

namespace mv {

namespace {
constexpr size_t kBatchTriangles = 1u << 20;
}  // namespace

uint64_t memory_budget(const BuildOptions& o) { return o.memory ? o.memory : default_host_memory(); }

size_t batch_triangles(const BuildOptions& o) {
  return static_cast<size_t>(std::clamp<uint64_t>(memory_budget(o) / 8 / 48, 4096, kBatchTriangles));
}

uint64_t vertex_share(const BuildOptions& o) { return memory_budget(o) / 4; }
uint64_t bucket_share(const BuildOptions& o) { return memory_budget(o) / 4; }

std::unique_ptr<io::MeshSource> open_budgeted_mesh(const BuildOptions& o, bool defer_vertices) {
  if (o.mesh) return io::memory_mesh(o.mesh->positions, o.mesh->indices, o.input, o.mesh->colours);
  return io::open_mesh(o.input, vertex_share(o), defer_vertices);
}

// Fails early, before the heavy work, when a mesh's host-side arrays would pass the budget: the positions
// (at most their RAM share), the used-vertex flags, and one batch of triangles with its indices (out of
// core, the bucketed triangles spill to disk past their share of the budget).
void check_mesh_memory(const BuildOptions& o, const io::MeshSource& mesh) {
  const uint64_t vertices = mesh.positions().size() / 3, triangles = mesh.triangles_hint();
  const uint64_t need = std::min(vertices * 12, vertex_share(o)) + vertices +
                        std::min<uint64_t>(triangles, batch_triangles(o)) * 48;
  if (need > memory_budget(o))
    throw CodedError(ErrorCode::out_of_memory,
                     o.input + ": the mesh needs about " + format_bytes(need) +
                         " of host memory, over the host memory budget " + format_bytes(memory_budget(o)),
                     setting_host_memory);
}

bool clips(const BuildOptions& o) { return o.placement.origin == GridPlacement::Origin::kCube; }

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
      throw CodedError(ErrorCode::input, o.input + ": the mesh lies outside the bounds", setting_bounds);
  }
  return g;
}

// Bounds of the vertices a mesh's faces use (scans carry unreferenced vertices) and their surface, for the
// plan: one streaming pass. `over_ranks`: a build in cubes, which every rank calls alike.
MeshSurvey survey_mesh(const BuildOptions& o, BuildReport* r, bool over_ranks) {
  MeshSurvey s;
  const bool shares = over_ranks && o.ranks && o.ranks->collectives;
  auto mesh = open_budgeted_mesh(o, shares);
  check_mesh_memory(o, *mesh);
  if (r) r->vertex_scratch_bytes = mesh->positions_mapped() ? mesh->positions().size_bytes() : 0;
  // Over ranks, each reads a share of the faces where the file allows (every rank alike); else all of them.
  if (shares) {
    if (survey_face_shares(*o.ranks->collectives, *mesh, batch_triangles(o), s)) return s;
    s = MeshSurvey();
    mesh = open_budgeted_mesh(o);
  }
  std::vector<bool> used;
  survey_faces(*mesh, batch_triangles(o), s, used);
  survey_used_vertices(mesh->positions(), used, s);
  if (mesh->rewind()) s.source = std::move(mesh);
  return s;
}

PlanBudgets plan_budgets(const BuildOptions& o, const Device* dev) {
  return {memory_budget(o), dev ? dev->memory_budget() : 0};
}

GridTransform plan_mesh(const BuildOptions& o, uint32_t resolution, MeshSurvey& survey, const Device& dev,
                        BuildReport& r, const PlanListener& on_plan) {
  const GridTransform grid = place_mesh_grid(o, resolution, survey.bounds);
  r.plan = plan_mesh_build(o, survey, grid, plan_budgets(o, &dev));
  if (on_plan) on_plan(r.plan);
  return grid;
}

void for_each_grid_batch(const BuildOptions& o, const GridTransform& grid, uint64_t& triangles,
                         const std::function<void(const std::vector<float>&, double)>& batch,
                         MeshColourInput* colours, bool face_share, const MeshShare* share,
                         double* open_seconds, std::shared_ptr<io::MeshSource> surveyed) {
  const auto opening = std::chrono::steady_clock::now();
  // With a share whose vertices were fetched from the ranks that read them, its own arrays; else the surveyed
  // source where it could start again, or the file opened anew.
  std::shared_ptr<io::MeshSource> mesh =
      share      ? io::memory_mesh(share->positions, share->indices, o.input, share->colours)
      : surveyed ? std::move(surveyed)
                 : open_budgeted_mesh(o);
  if (open_seconds) *open_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - opening).count();
  if (face_share && !share && !mesh->select_face_share(o.ranks->collectives->rank, o.ranks->collectives->size))
    throw Error(o.input + ": the mesh changed while it was read (its faces can no longer be shared by offset)");
  uint64_t ordinal = share ? share->first_triangle : mesh->first_triangle();  // of the batch's first triangle
  const std::span<const uint32_t> vertex_rgb = mesh->vertex_colours(), vertex_tex = mesh->vertex_textures();
  const std::span<const float> vertex_uv = mesh->vertex_uvs();
  if (colours) {
    const bool has = !vertex_rgb.empty() || !vertex_tex.empty();
    if (o.attributes == Attributes::rgb && !has)
      throw CodedError(ErrorCode::invalid_argument,
                       o.input + ": --attributes rgb, but the mesh has no vertex colours or textures", setting_none);
    colours->wanted = o.attributes != Attributes::none && has;
    if (colours->wanted) colours->colours.textures = mesh->textures();
  }
  const bool keep = colours && colours->wanted;
  std::vector<uint32_t> idx, kept;
  std::vector<float> tris;
  const double faces = std::max<double>(1, double(mesh->triangles_hint()));
  while (mesh->next_triangles(idx, batch_triangles(o))) {
    tris.clear();
    kept.clear();
    triangles_to_grid(grid, mesh->positions(), idx.data(), idx.size() / 3, tris, clips(o), keep ? &kept : nullptr);
    triangles += tris.size() / 9;
    if (keep) {
      if (colours->keep_tris) colours->tris.insert(colours->tris.end(), tris.begin(), tris.end());
      MeshTriangleColours& c = colours->colours;
      for (uint32_t t : kept) {
        const uint32_t* v = &idx[3 * size_t{t}];
        for (int k = 0; k < 3; ++k) c.rgb.push_back(vertex_rgb.empty() ? 0xffffffu : vertex_rgb[v[k]]);
        c.texture.push_back(vertex_tex.empty() ? io::kNoTexture : vertex_tex[v[0]]);
        if (!colours->keep_tris) c.ordinal.push_back(static_cast<uint32_t>(ordinal + t));
        for (int k = 0; k < 3 && !vertex_tex.empty(); ++k)
          c.uv.insert(c.uv.end(), {vertex_uv[2 * size_t{v[k]}], vertex_uv[2 * size_t{v[k]} + 1]});
        if (vertex_tex.empty()) c.uv.insert(c.uv.end(), 6, 0.0f);
      }
    }
    ordinal += idx.size() / 3;
    batch(tris, std::min(1.0, double(triangles) / faces));
  }
}

}  // namespace mv

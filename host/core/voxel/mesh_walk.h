// Reading a mesh for a build (host/core/voxel/build_pipeline.cpp): the host budget's shares, the survey of the
// faces (bounds, surface, the plan), and the walk that hands the triangles over in grid units, a batch at a time.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "io/mesh_source.h"
#include "megavox/build.h"
#include "megavox/device.h"
#include "megavox/voxelize.h"
#include "voxel/build_plan.h"
#include "voxel/mesh_colours.h"

namespace mv {

uint64_t memory_budget(const BuildOptions& o);
// Triangles read per batch: up to 1 Mi, at most an eighth of the budget (48 bytes each with the indices).
size_t batch_triangles(const BuildOptions& o);
// How the host budget is shared: a PLY's vertex positions stay in RAM up to a quarter of it (past it, in a
// mapped scratch file), out of core the triangle buckets another quarter (past it, spilled); voxel keys get
// the rest.
uint64_t vertex_share(const BuildOptions& o);
uint64_t bucket_share(const BuildOptions& o);

// `defer_vertices`: a build over ranks, whose ranks read a binary PLY's vertices in shares where they can.
std::unique_ptr<io::MeshSource> open_budgeted_mesh(const BuildOptions& o, bool defer_vertices = false);
// Fails early, before the heavy work, when a mesh's host-side arrays would pass the budget.
void check_mesh_memory(const BuildOptions& o, const io::MeshSource& mesh);
// Whether triangles are clipped to an explicit cube (--bounds).
bool clips(const BuildOptions& o);
// The grid around a mesh's bounds; with an explicit cube the stored bounds become the part inside it.
GridTransform place_mesh_grid(const BuildOptions& o, uint32_t resolution, Bounds& bounds);
// Bounds of the vertices a mesh's faces use and their surface, for the plan: one streaming pass. `over_ranks`: a
// build in cubes, which every rank calls alike.
MeshSurvey survey_mesh(const BuildOptions& o, BuildReport* r, bool over_ranks = false);
PlanBudgets plan_budgets(const BuildOptions& o, const Device* dev);
// The grid around the surveyed mesh, and the plan announced before the voxels are built.
GridTransform plan_mesh(const BuildOptions& o, uint32_t resolution, MeshSurvey& survey, const Device& dev,
                        BuildReport& r, const PlanListener& on_plan);

// A mesh's triangles kept for its voxel colours: in grid units, with their vertex colours (3 each).
struct MeshColourInput {
  bool keep_tris = true;  // in core; out of core the buckets carry the triangles with their colours
  bool wanted = false;    // --attributes and the mesh's vertex colours or textures say so
  std::vector<float> tris;
  MeshTriangleColours colours;  // per triangle, from the first (out of core: the batch's, cleared by the caller)
  Fragments fragments;          // in core: what the voxelizer met, for the colours
};

// Streams a mesh's triangles in grid units, a batch at a time; with `colours`, decides from --attributes and the
// mesh whether voxel colours are built and, if so, keeps every triangle with its vertex colours there. `share`: a
// rank's faces with the vertices fetched for them; `open_seconds`: the time the source took to open; `surveyed`:
// the survey's source where it can walk its faces again (else the file is opened anew).
void for_each_grid_batch(const BuildOptions& o, const GridTransform& grid, uint64_t& triangles,
                         const std::function<void(const std::vector<float>&, double)>& batch,
                         MeshColourInput* colours = nullptr, bool face_share = false,
                         const MeshShare* share = nullptr, double* open_seconds = nullptr,
                         std::shared_ptr<io::MeshSource> surveyed = nullptr);

}  // namespace mv
